#!/usr/bin/env bash
# Solver × warm start (docs/solvers.md "Solver × warm start"): per scene family one paired bench
# with the solver comparison (docs/bench.md "Solver comparison") — pgs, nncg and newton-sparse,
# each from zero, builtin, cnn and copy, accuracy target R = 1e-6 (natural-map residual relative
# to the heaviest weight), cap 10,000 iterations, θ ≤ 1e-2 N for the total column — on the
# family's held-out evaluation seeds ([family] seeds; the models were trained on others), then
# research/scripts/solver-comparison-table.py prints the table. `make results PART=solvers` runs
# this script (STEPS=2) and writes the table into docs/results/solvers.md and the docs' quotes.
#
#   research/scripts/solver-comparison.sh [BUILD_DIR] [OUT_DIR]   (defaults: build, results/solvers)
#
# Environment: ONLY="impact deep" (a subset of: seed impact deep pour drum polydisperse box_pile;
# impact_1000, the impact family at 1,000 bodies, ~15 min on 2 shared cores, only when named),
# SEEDS (instead of each family's seeds), STEPS=N (evaluated steps per seed, default 10),
# DEEP_ORACLE=1 (the oracle on the settled deep pile too, which `copy` needs; default off: deep
# then runs --no-oracle without copy), SOLVERS (default pgs,nncg,newton-sparse), NO_DOCS=1 (do not
# print the table).
# Bounded: ~10 evaluated steps per seed and 2 seeds (1 on deep) keep a family to a few minutes
# on 2 idle cores; it is not part of `make test`. The CPU model and the load are recorded next
# to the reports (OUT_DIR/machine.txt) and in the table.
set -euo pipefail
cd "$(dirname "$0")/../.."
BUILD=${1:-build}
OUT=${2:-results/solvers}
DC="$BUILD/bin/deepcontact"
[[ -x "$DC" ]] || { echo "solver-comparison: $DC not found (build the deepcontact target first)" >&2; exit 2; }
ONLY=${ONLY:-"seed impact deep pour drum polydisperse box_pile"}
N=${STEPS:-10}
SOLVERS=${SOLVERS:-pgs,nncg,newton-sparse}
mkdir -p "$OUT"
{ lscpu | grep 'Model name'; nproc; uptime; date -u; } > "$OUT/machine.txt"
want() { [[ " $ONLY " == *" $1 "* ]]; }
window() { echo "--warmup-steps $1 --steps $(($1 + N))"; }  # N steps from step $1 on
run() {  # name, seeds, then bench arguments
  local name=$1 seeds=$2; shift 2
  [[ -n "${SEEDS:-}" ]] && seeds=$SEEDS
  echo "== $name: $DC bench --solvers $SOLVERS --accuracy 1e-6 --seeds $seeds $*" | tee "$OUT/$name.cmd"
  uptime > "$OUT/$name.load"
  /usr/bin/time -v "$DC" bench --solvers "$SOLVERS" --accuracy 1e-6 --seeds "$seeds" --sweeps 1000 --max-sweeps 10000 \
    "$@" --out "$OUT/$name" 2> >(tee "$OUT/$name.time" >&2) | tee "$OUT/$name.txt"
  uptime >> "$OUT/$name.load"
}
S=zero,builtin,cnn,copy
# The seed scene's pile, settled (the bench's default scene; seeds 1..2 of its evaluation seeds).
want seed && run seed 1..2 --scene scenes/seed.toml --warmstarts "$S" $(window 300)
# From just before the impact (step 195) through it.
want impact && run impact 1..2 --scene scenes/impact.toml --warmstarts "$S" $(window 195)
# The impact family at 1,000 bodies (scenes/impact_1000.toml), through the impact (~step 222);
# only when ONLY names it. N = 6 keeps it to ~15 min on 2 shared cores.
want impact_1000 && run impact_1000 1..2 --scene scenes/impact_1000.toml --warmstarts zero,builtin,copy $(window 221)
# The settled deep pile (steps 480..): 1,000 bodies.
if want deep; then
  if [[ "${DEEP_ORACLE:-0}" == 1 ]]; then
    run deep 1 --scene scenes/deep.toml --warmstarts "$S" $(window 480)
  else
    run deep 1 --scene scenes/deep.toml --warmstarts zero,builtin,cnn $(window 480) --no-oracle
  fi
fi
want pour && run pour 1..2 --scene scenes/pour.toml --warmstarts "$S" $(window 200)
want drum && run drum 1..2 --scene scenes/drum.toml --warmstarts "$S" $(window 100)
want polydisperse && run polydisperse 1..2 --scene scenes/polydisperse.toml --warmstarts "$S" $(window 185)
want box_pile && run box_pile 1..2 --scene scenes/box_pile.toml --warmstarts "$S" $(window 250)
if [[ "${NO_DOCS:-0}" != 1 ]]; then
  /usr/bin/python3 research/scripts/solver-comparison-table.py "$OUT"
fi
echo "solver-comparison: reports under $OUT/*/report.md"
