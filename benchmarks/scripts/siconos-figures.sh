#!/usr/bin/env bash
# Reproduces the figures of docs/lcp.md "Side by side with Siconos": exports the frictional
# problems of the impact scene (steps 105 and 210: the settled pile, and just after the heavy
# disc hits it) and of the deep scene (steps 250 and 500), then runs siconos_compare on them and
# on Siconos' 2D test files of ≥ 300 contacts, writing a CSV next to the printed table.
#
#   benchmarks/scripts/siconos-figures.sh [BUILD] [OUT]     (defaults: build, results/siconos)
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
ours=newton
"$BUILD/bin/deepcontact" lcp solve "$ROOT/tests/data/fc2d/FrictionContactProblem00394.dat" --solver newton-sparse \
  >/dev/null 2>&1 && ours=newton,newton-sparse
D=$ROOT/tests/data/fc2d
OPENBLAS_NUM_THREADS=1 "$BUILD/bin/siconos_compare" --ours "$ours" --siconos nsgs,cpg,lemke --csv "$OUT/compare.csv" \
  "$D/FrictionContactProblem00237.dat" "$D/FrictionContactProblem00727.dat" \
  "$D/fc2d_granularflowonwall_00667_00000.dat" "$D/fc2d_granularflowonwall_02020_00213.dat" \
  "$D/fc2d_granularflowonwall_07002_00801.dat" \
  "$OUT"/impact/*.hdf5 "$OUT"/deep/*.hdf5
uptime
