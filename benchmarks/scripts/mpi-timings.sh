#!/usr/bin/env bash
# The MPI figures of docs/cluster.md "Measuring it": wall and CPU time of generate --sims 16 and
# of a quick bench over 4 seeds at K = 1 and K = 2 ranks (one thread per rank), with the
# writer's/gatherer's share, and training samples/s at K = 1 and 2.
# Usage: benchmarks/scripts/mpi-timings.sh [BUILD_DIR] [STEPS]   (STEPS per simulation/seed, default 600)
set -euo pipefail
cd "$(dirname "$0")/../.."
BUILD=${1:-build}
STEPS=${2:-600}
DC=$PWD/$BUILD/bin/deepcontact
MPIRUN=(mpirun --allow-run-as-root --oversubscribe --mca btl self,vader)
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
export OMP_NUM_THREADS=1
timed() {  # label, command...
  local label=$1; shift
  /usr/bin/time -f "$label: wall %e s, CPU user+sys %U+%S s" "$@" >"$work/out.txt" 2>"$work/time.txt" || {
    cat "$work/time.txt" >&2; exit 1; }
  tail -1 "$work/time.txt"
  grep -E "writer spent|rank 0 ran|written in|data-parallel|samples \(every" "$work/out.txt" || true
}
echo "CPU: $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | xargs), $(nproc --all) cores; load: $(cut -d' ' -f1-3 /proc/loadavg)"
timed "generate --sims 16 K=1" "$DC" generate --sims 16 --steps "$STEPS" --threads 1 --out "$work/g1.h5"
timed "generate --sims 16 K=2" "${MPIRUN[@]}" -n 2 "$DC" generate --sims 16 --steps "$STEPS" --threads 1 --out "$work/g2.h5"
timed "bench --quick --seeds 1..4 K=1" "$DC" bench --quick --seeds 1..4 --steps "$STEPS" --out "$work/b1"
timed "bench --quick --seeds 1..4 K=2" "${MPIRUN[@]}" -n 2 "$DC" bench --quick --seeds 1..4 --steps "$STEPS" --out "$work/b2"
for k in 1 2; do
  "${MPIRUN[@]}" -n $k "$DC" train --data "$work/g1.h5" --every 4 --epochs 2 --batch 32 --val 0 --threads 1 --no-plot \
    --out "$work/m$k.h5" >"$work/train$k.txt"
  n=$(grep -oE 'train: [0-9]+ samples' "$work/train$k.txt" | grep -oE '[0-9]+')
  /usr/bin/python3 - "$work/train$k.txt" "$n" "$k" <<'PYEOF'
import re, sys
text = open(sys.argv[1]).read()
secs = [float(s) for s in re.findall(r"epoch +\d+/\d+ .* ([0-9.]+) s", text)]
n = int(sys.argv[2])
# --val 0: every sample trains; samples/s over both epochs
print("train K=%s: %d samples, epochs %s s -> %.1f samples/s" % (sys.argv[3], n, secs, n * len(secs) / sum(secs)))
PYEOF
done
