#!/usr/bin/env bash
# Reproduces the figures of docs/lcp.md "Side by side with Siconos": exports the frictional
# problems of the impact scene (steps 105 and 210: the settled pile, and just after the heavy
# disc hits it) and of the deep scene (steps 250 and 500), then runs siconos_compare on them and
# on Siconos' 2D test files of ≥ 300 contacts, writing a CSV next to the printed table.
#
#   [MAX_ITER=20000] [REPEAT=3] benchmarks/scripts/siconos-figures.sh [BUILD] [OUT]
#   (defaults: build, results/siconos; OUT/compare.csv is appended to)
#
# Needs a build with siconos_compare (scripts/install-deps.sh --siconos). Prints the CPU model
# and the load, as every figure of the project does.
set -euo pipefail
ROOT=$(cd "$(dirname "$0")/../.." && pwd)
BUILD=${1:-$ROOT/build}
OUT=${2:-$ROOT/results/siconos}
mkdir -p "$OUT"
lscpu | grep 'Model name'
uptime
"$BUILD/bin/deepcontact" simulate --scene "$ROOT/scenes/impact.toml" --steps 210 \
  --export-problems "$OUT/impact" --every 105
"$BUILD/bin/deepcontact" simulate --scene "$ROOT/scenes/deep.toml" --steps 500 \
  --export-problems "$OUT/deep" --every 250
# Ours: newton-sparse, nncg (3000 sweeps) and the proximal-point route around newton-sparse
# (dc/lcp/proximal_point.hpp). Siconos: NSGS in sparse-block storage, capped at MAX_ITER
# iterations (default 20000: one NSGS solve of the 7002-contact file stays within seconds); where
# it stops at the cap its residual is above ours and NSGS / ours is a lower bound of the speed-up.
# CPG and Lemke (dense) are left out here: minutes per problem of a few hundred contacts.
D=$ROOT/tests/data/fc2d
OPENBLAS_NUM_THREADS=1 "$BUILD/bin/siconos_compare" --ours newton-sparse,nncg,proximal:newton-sparse --siconos nsgs \
  --max-iter "${MAX_ITER:-20000}" --repeat "${REPEAT:-3}" --csv "$OUT/compare.csv" \
  "$D/FrictionContactProblem00237.dat" "$D/FrictionContactProblem00727.dat" \
  "$D/fc2d_granularflowonwall_00667_00000.dat" "$D/fc2d_granularflowonwall_02020_00213.dat" \
  "$D/fc2d_granularflowonwall_07002_00801.dat" \
  "$OUT"/impact/*.hdf5 "$OUT"/deep/*.hdf5
uptime
