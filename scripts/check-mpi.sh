#!/usr/bin/env bash
# The MPI check of CI (docs/cluster.md): generate, bench and train under
# `mpirun -n 2` against one-process runs of the same binary.
#   1. generate: the 2-rank data set equals the 1-process one in every dataset and attribute
#      (the shard list aside, which names the run); a 1-process run killed mid-way (SIGKILL)
#      and resumed on 2 ranks, and a 2-rank run whose rank 1 is killed and resumed in one
#      process, give that data set too.
#   2. bench (quick starters, 2 seeds, short scenes, the solver comparison of pgs and nncg):
#      summary.json and results.h5 of the 2-rank run equal the 1-process run's except the timings.
#   3. train (2 epochs): mpirun -n 1 equals a plain run bit for bit; two 2-rank runs are
#      equal (deterministic for fixed K); the 2-rank model is close to the 1-rank one.
# Usage: scripts/check-mpi.sh [BUILD_DIR]   (default build; needs build/bin/deepcontact)
# ~1-2 minutes on 2 idle cores. Exit status 0 = all equalities hold.
set -euo pipefail
cd "$(dirname "$0")/.."
BUILD=${1:-build}
DC=$PWD/$BUILD/bin/deepcontact
PY=/usr/bin/python3
MPIRUN=(mpirun --allow-run-as-root --oversubscribe --mca btl self,vader)
command -v mpirun >/dev/null || { echo "check-mpi: mpirun not found (scripts/install-deps.sh installs openmpi-bin)" >&2; exit 1; }
[ -x "$DC" ] || { echo "check-mpi: $DC not built" >&2; exit 1; }
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
export OMP_NUM_THREADS=1  # one thread per rank on 2 cores; the 1-process runs alike
t_all=$SECONDS
step() { echo "check-mpi: $*"; }

# ---- 1. generate ---------------------------------------------------------------------
FAM=(--set world.width=12 --set world.height=12 --set bodies.mean=[6.0,6.0] --set bodies.sigma=2.0 --seed 5
     --count 10..14 --threads 1)
"$DC" generate --sims 6 "${FAM[@]}" --steps 80 --out "$work/one.h5" >/dev/null
"${MPIRUN[@]}" -n 2 "$DC" generate --sims 6 "${FAM[@]}" --steps 80 --out "$work/two.h5" >"$work/two.log"
grep -q "2 ranks x" "$work/two.log"
$PY scripts/h5_compare.py "$work/one.h5" "$work/two.h5" --ignore '^/shards'  # shard list names the run
step "generate: 2 ranks = 1 process"

# Slower simulations (1,200 steps, ~0.3 s each on one core) so that a kill lands between commits.
SLOW=(--sims 6 "${FAM[@]}" --steps 1200)
"$DC" generate "${SLOW[@]}" --out "$work/ref.h5" >/dev/null
# (a) one process interrupted after 2 committed, resumed on 2 ranks
"$DC" generate "${SLOW[@]}" --log-completed --out "$work/a.h5" >/dev/null 2>"$work/a.log" &
pid=$!
until grep -q "completed 1 " "$work/a.log" 2>/dev/null || ! kill -0 $pid 2>/dev/null; do sleep 0.05; done
# SIGKILL at an arbitrary instant: committed shards are complete files (scripts/kill-test.sh
# does this hundreds of times).
kill -KILL $pid 2>/dev/null || true
wait $pid 2>/dev/null || true
[ -f "$work/a.h5.partial" ] || { echo "check-mpi: the 1-process run finished before it was killed" >&2; exit 1; }
"${MPIRUN[@]}" -n 2 "$DC" generate "${SLOW[@]}" --resume --out "$work/a.h5" >/dev/null
$PY scripts/h5_compare.py "$work/ref.h5" "$work/a.h5" --ignore '^/shards'
step "generate: 1 process killed (SIGKILL), resumed on 2 ranks = uninterrupted"
# (b) 2 ranks, rank 1 killed right after its first simulation is committed, resumed in one
# process. Simulations go round-robin (simulation i on rank i mod 2), so rank 1 commits
# simulation 1 first and still has 3 and 5 to do (~0.6 s) when it is killed. mpirun then
# SIGTERMs rank 0, which stops at its next step (SigintGuard), or SIGKILLs it. On a loaded
# machine the kill can still come too late (the run finished): that is retried, up to 3 times.
victim=""
for attempt in 1 2 3; do
  rm -rf "$work"/b.h5* "$work/b.log"
  "${MPIRUN[@]}" --mca odls_base_sigkill_timeout 30 -n 2 "$DC" generate "${SLOW[@]}" --log-completed --out "$work/b.h5" \
    >/dev/null 2>"$work/b.log" &
  mpid=$!
  until grep -q "completed 1 " "$work/b.log" 2>/dev/null || ! kill -0 $mpid 2>/dev/null; do sleep 0.02; done
  victim=""
  for p in $(pgrep -P $mpid); do
    if tr '\0' '\n' </proc/$p/environ 2>/dev/null | grep -qx "OMPI_COMM_WORLD_RANK=1"; then victim=$p; fi
  done
  [ -n "$victim" ] && kill -9 "$victim" 2>/dev/null || true
  wait $mpid 2>/dev/null || true
  [ -f "$work/b.h5.partial" ] && break
  echo "check-mpi: attempt $attempt: the 2-rank run finished before rank 1 was killed; again" >&2
  victim=""
done
[ -n "$victim" ] && [ -f "$work/b.h5.partial" ] || { echo "check-mpi: the 2-rank run finished before rank 1 was killed, 3 times" >&2; exit 1; }
"$DC" generate "${SLOW[@]}" --resume --out "$work/b.h5" >/dev/null
$PY scripts/h5_compare.py "$work/ref.h5" "$work/b.h5" --ignore '^/shards'
step "generate: rank 1 of 2 killed (pid ${victim:-none}), resumed in 1 process = uninterrupted"

# ---- 2. bench ------------------------------------------------------------------------
BENCH=(bench --quick --seeds 1..2 --steps 60 --solvers pgs,nncg)  # the solver comparison joins across ranks too
"$DC" "${BENCH[@]}" --out "$work/bench1" >/dev/null
"${MPIRUN[@]}" -n 2 "$DC" "${BENCH[@]}" --out "$work/bench2" >"$work/bench2.log"
grep -q "2 ranks" "$work/bench2.log"
TIMING='(_ms|ms_to_|ns_per_row|wall_seconds|@date|@git|@machine|@build)'
# /solvers/intervals mixes timing columns with the others; summary.json's comparison below
# checks the solver comparison's non-timing figures (reached share, iterations).
$PY scripts/h5_compare.py "$work/bench1/results.h5" "$work/bench2/results.h5" --ignore "$TIMING" \
  --ignore '^/statistics/.*(time|total|ms)' --ignore '^/solvers/intervals$'
$PY - "$work/bench1/summary.json" "$work/bench2/summary.json" <<'PYEOF'
import json, re, sys
timing = re.compile(r"(_ms|ns_per_row|seconds|date|git|machine|build|provenance|total)")  # timings and ratios of timings
def strip(x):
    if isinstance(x, dict):
        return {k: strip(v) for k, v in x.items() if not timing.search(k)}
    if isinstance(x, list):
        return [strip(v) for v in x]
    return x
a, b = (strip(json.load(open(p))) for p in sys.argv[1:3])
if a != b:
    print("check-mpi: summary.json differs beyond timings"); sys.exit(1)
print("check-mpi: summary.json equal except timings")
PYEOF
step "bench: 2 ranks = 1 process (except timings)"

# ---- 3. train ------------------------------------------------------------------------
TRAIN=(train --data "$work/ref.h5" --epochs 2 --batch 16 --threads 1 --no-plot)
"$DC" "${TRAIN[@]}" --out "$work/m1.h5" >/dev/null
"${MPIRUN[@]}" -n 1 "$DC" "${TRAIN[@]}" --out "$work/m1mpi.h5" >/dev/null
$PY scripts/h5_compare.py "$work/m1.h5" "$work/m1mpi.h5" --ignore '(seconds|date|time)'
step "train: mpirun -n 1 = plain run"
"${MPIRUN[@]}" -n 2 "$DC" "${TRAIN[@]}" --out "$work/m2a.h5" >"$work/m2a.log"
"${MPIRUN[@]}" -n 2 "$DC" "${TRAIN[@]}" --out "$work/m2b.h5" >/dev/null
grep -q "data-parallel over 2 ranks" "$work/m2a.log"
$PY scripts/h5_compare.py "$work/m2a.h5" "$work/m2b.h5" --ignore '(seconds|date|time)'
step "train: 2 ranks deterministic"
$PY - "$work/m1.h5" "$work/m2a.h5" <<'PYEOF'
import sys, h5py, numpy as np
worst = 0.0
with h5py.File(sys.argv[1]) as a, h5py.File(sys.argv[2]) as b:
    def visit(name, obj):
        global worst
        if isinstance(obj, h5py.Dataset) and obj.dtype.kind == "f" and name.startswith("weights"):
            x, y = obj[()], b[name][()]
            worst = max(worst, float(np.max(np.abs(x - y)) / max(1e-12, float(np.max(np.abs(x))))))
    a.visititems(visit)
print("check-mpi: train: max |w(K=2) - w(K=1)| / max |w| = %.3g (rounding of the regrouped gradient sum)" % worst)
sys.exit(0 if worst < 1e-3 else 1)
PYEOF
step "all equalities hold ($((SECONDS - t_all)) s)"
