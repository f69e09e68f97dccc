#!/usr/bin/env bash
# World steps with pgs-colored on 1 and 2 OpenMP threads: a 10,000-circle pile from the first step
# (100 × 100 circles of radius 0.5 on a hexagonal lattice with 0.5 mm gaps, in a 100.6 m wide
# box: ~30,000 contacts once they touch), STEPS steps of SWEEPS fixed sweeps (tolerance 0, so
# both thread counts do the same work), builtin warm start. Prints per binary and thread
# count the median over ROUNDS alternated runs of the mean wall ms per step (total and solve,
# `simulate --profile`), the mean rows per step, the 2-thread speed-ups, and the final state's
# hash, which must be the same for every binary and thread count (the solver's results do not
# depend on the threads). Wall-clock figures mean something only on a quiet machine (`uptime`).
#
#   benchmarks/scripts/threads-step.sh [DEEPCONTACT ...]      (default: build/bin/deepcontact)
#
# Environment: STEPS (default 200), SWEEPS (default 100), ROUNDS (default 3), OMP_WAIT_POLICY
# (default active).
set -euo pipefail
cd "$(dirname "$0")/../.."
BINS=("$@")
[[ ${#BINS[@]} -gt 0 ]] || BINS=(build/bin/deepcontact)
STEPS=${STEPS:-200}
SWEEPS=${SWEEPS:-100}
ROUNDS=${ROUNDS:-3}
export OMP_WAIT_POLICY=${OMP_WAIT_POLICY:-active}
OUT=$(mktemp)
SCENE=$(mktemp --suffix=.toml)
trap 'rm -f "$OUT" "$SCENE"' EXIT
python3 - "$SCENE" <<'EOF'
import math, sys
with open(sys.argv[1], "w") as f:
    f.write("[world]\nwidth = 100.6\nheight = 100.0\n\n[bodies]\ncount = 0\n")
    for row in range(100):
        y = 0.5005 + row * (math.sqrt(3) / 2 + 0.0005)
        for col in range(100):
            x = 0.5005 + col * 1.0005 + (0.5 if row % 2 else 0.0)
            f.write(f"\n[[body]]\nposition = [{x:.4f}, {y:.4f}]\nradius = 0.5\n")
EOF
echo "threads-step: CPU: $(lscpu | sed -n 's/^Model name: *//p' | head -1), $(nproc) CPUs; OMP_WAIT_POLICY=$OMP_WAIT_POLICY"
echo "threads-step: $STEPS steps x $SWEEPS sweeps, 10,000 circles; load before: $(cut -d' ' -f1-3 /proc/loadavg)"
for round in $(seq 1 "$ROUNDS"); do
  for i in "${!BINS[@]}"; do
    for t in 1 2; do
      res=$("${BINS[$i]}" simulate --scene "$SCENE" --set solver.sweeps="$SWEEPS" --set solver.tolerance=0 \
        --set solver.name=pgs-colored:$t --steps "$STEPS" --profile --hash 2> /dev/null)
      hash=$(head -1 <<< "$res")
      prof=$(grep '^profile ' <<< "$res")
      get() { sed -n "s/.* $1=\([^ ]*\).*/\1/p" <<< "$prof"; }
      echo "$i $t $(get total_ms) $(get solve_ms) $(get rows) $hash" >> "$OUT"
    done
  done
done
echo "threads-step: load after: $(cut -d' ' -f1-3 /proc/loadavg)"
python3 - "$OUT" "${BINS[@]}" <<'EOF'
import statistics, sys
rows = [l.split() for l in open(sys.argv[1])]
bins = sys.argv[2:]
print(f"{'binary':<48} {'thr':>3} | {'step ms':>8} {'solve ms':>8} {'rows':>7} | hash")
for i, b in enumerate(bins):
    med = {}
    for t in ("1", "2"):
        sel = [r for r in rows if r[0] == str(i) and r[1] == t]
        med[t] = [statistics.median(float(r[k]) for r in sel) for k in (2, 3, 4)]
        print(f"{b[-48:]:<48} {t:>3} | {med[t][0]:8.2f} {med[t][1]:8.2f} {med[t][2]:7.0f} | "
              f"{' '.join(sorted(set(r[5] for r in sel)))}")
    print(f"{'':<48} 2/1 | {med['1'][0] / med['2'][0]:7.2f}x {med['1'][1] / med['2'][1]:7.2f}x  "
          f"(median of {len(sel)} runs)")
EOF
