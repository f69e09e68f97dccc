#!/usr/bin/env bash
# The scene-family measurements (docs/design.md §8.5, docs/scenes.md "Families", docs/research.md):
# per family a paired bench of zero, builtin and the two non-learned baselines (and sph, the
# oracle grid, where the oracle is affordable), with the residual at a fixed budget and
# sweeps to tol with a higher cap (medians saturate at the cap on deep piles), then sweeps
# against pile height on deep and a size sweep keeping the shape.
#
#   research/scripts/families-bench.sh [BUILD_DIR] [OUT_DIR]        (defaults: build, results/families)
#
# Environment: SEEDS (default: each family's own [family] seeds), STARTERS (default
# zero,builtin,builtin-extrapolate,builtin-gain-extrapolate,builtin-statics,cnn: the
# non-learned starters and the shipped cnn, which runs on every box), ORACLES (default
# sph,sph-residual,sph-gain:poly6:0.5:0.5,sph-gain-add:poly6:0.5:0.5,copy-noise:0.01,
# copy-noise:0.1,copy-noise:0.3: oracle starters where the oracle is affordable; the gain
# oracles on the learned models' grid), FAMILY_MODELS=1 (add
# cnn:models/<family>.h5 where that file exists), QUICK=1 (fewer steps and seeds: the first
# look under load), MID=1 (the windows of docs/research.md's per-family tables, 2 seeds),
# ONLY="deep impact" (a subset of the runs: deep impact pour polydisperse drum mixed height
# scale cnn-scale).
# Each run stays under ~10 min on an idle 2-core machine; QUICK=1 under ~5 min under load.
set -euo pipefail
cd "$(dirname "$0")/../.."
BUILD=${1:-build}
OUT=${2:-results/families}
DC="$BUILD/bin/deepcontact"
[[ -x "$DC" ]] || { echo "families-bench: $DC not found (build the deepcontact target first)" >&2; exit 2; }
S=${STARTERS:-zero,builtin,builtin-extrapolate,builtin-gain-extrapolate,builtin-statics,cnn}
O=${ORACLES:-sph,sph-residual,sph-gain:poly6:0.5:0.5,sph-gain-add:poly6:0.5:0.5,copy-noise:0.01,copy-noise:0.1,copy-noise:0.3}
ONLY=${ONLY:-"deep impact pour polydisperse drum mixed height scale cnn-scale"}
# The family's own PGS-trained model, when asked for and present (scripts/train-family-model.sh).
fam() { if [[ "${FAMILY_MODELS:-0}" == 1 && -f "models/$1.h5" ]]; then echo ",cnn:models/$1.h5"; fi; }
mkdir -p "$OUT"
seeds() { if [[ -n "${SEEDS:-}" ]]; then echo "--seeds $SEEDS"; elif [[ "${QUICK:-0}${MID:-0}" == *1* ]]; then echo "--seeds $1"; fi; }
want() { [[ " $ONLY " == *" $1 "* ]]; }
run() {  # name, then bench arguments
  local name=$1; shift
  echo "== $name: $DC bench $*" | tee "$OUT/$name.cmd"
  /usr/bin/time -v "$DC" bench "$@" --out "$OUT/$name" 2> >(tee "$OUT/$name.time" >&2) | tee "$OUT/$name.txt"
}
if [[ "${QUICK:-0}" == 1 ]]; then
  DEEP="--warmup-steps 350 --steps 362"; IMPACT="--warmup-steps 200 --steps 250"; POUR="--warmup-steps 200 --steps 300"
  POLY="--steps 250"; HEIGHT="--scale 125,250,500 --warmup-steps 350 --steps 360"; SCALE="--scale 300,600,1000 --steps 200"
  DRUM="--warmup-steps 100 --steps 200"; MIXED="--steps 200"; CNNSCALE="--scale 250,500 --warmup-steps 195 --steps 240"
elif [[ "${MID:-0}" == 1 ]]; then
  DEEP="--warmup-steps 350 --steps 362"; IMPACT="--warmup-steps 195 --steps 260"; POUR="--warmup-steps 200 --steps 260"
  POLY="--steps 200"; HEIGHT="--scale 125,250,500 --warmup-steps 350 --steps 360"; SCALE="--scale 300,600,1000 --steps 200"
  DRUM="--warmup-steps 100 --steps 200"; MIXED="--steps 200"; CNNSCALE="--scale 250,500,1000 --warmup-steps 195 --steps 240"
else
  DEEP="--warmup-steps 350 --steps 400"; IMPACT="--warmup-steps 195 --steps 300"; POUR="--warmup-steps 150 --steps 400"; POLY="--steps 400"
  HEIGHT="--scale 125,250,500,1000 --warmup-steps 350 --steps 370"; SCALE="--scale 300,600,1000,2000 --steps 300"
  DRUM="--steps 600"; MIXED="--steps 400"; CNNSCALE="--scale 250,500,1000,2000 --warmup-steps 195 --steps 300"
fi
# deep: 1,000 bodies, the settled pile; the oracle (20000 sweeps + Newton per step) is skipped.
want deep && run deep --scene scenes/deep.toml --warmstarts "$S$(fam deep)" $(seeds 1..1) $DEEP --no-oracle --max-sweeps 10000
# deep, later: the settled pile (steps 480..).
want deep && run deep-late --scene scenes/deep.toml --warmstarts "$S$(fam deep)" $(seeds 1..1) --warmup-steps 480 --steps 488 \
  --no-oracle --max-sweeps 10000
want impact && run impact --scene scenes/impact.toml --warmstarts "$S$(fam impact),$O" $(seeds 1..2) $IMPACT --max-sweeps 10000
want pour && run pour --scene scenes/pour.toml --warmstarts "$S$(fam pour),$O" $(seeds 1..2) $POUR --max-sweeps 10000
want polydisperse && run polydisperse --scene scenes/polydisperse.toml --warmstarts "$S$(fam polydisperse),$O" $(seeds 1..2) \
  $POLY --max-sweeps 10000
# The rotating drum (kinematic paddles, no walls) and the mixed-shape pile have no [family]
# seeds: 1..2 (QUICK/MID) or 1..4. The shipped cnn sees the 10 circle channels; models/mixed.h5 adds the shape channels.
want drum && run drum --scene scenes/drum.toml --warmstarts "$S$(fam drum),$O" --seeds "${SEEDS:-$([[ "${QUICK:-0}${MID:-0}" == *1* ]] && echo 1..2 || echo 1..4)}" \
  $DRUM --max-sweeps 10000
want mixed && run mixed --scene scenes/mixed.toml --warmstarts "$S$(fam mixed),$O" --seeds "${SEEDS:-$([[ "${QUICK:-0}${MID:-0}" == *1* ]] && echo 1..2 || echo 1..4)}" \
  $MIXED --max-sweeps 10000
# Sweeps against pile height: deep at the same width, 125..1000 bodies (≈10..80 layers).
want height && run deep-height --scene scenes/deep.toml --warmstarts "$S" --seeds 1 $HEIGHT --scale-axis height \
  --scale-oracle-max 0 --no-oracle --max-sweeps 10000
# Size sweep keeping the shape (aspect ratio and filling): the polydisperse pile, oracle up to 600 bodies.
want scale && run polydisperse-scale --scene scenes/polydisperse.toml --warmstarts "$S" --seeds 1 $SCALE \
  --max-sweeps 10000
# N*: the size sweep of the impact family (box sides x sqrt(N/250)) with builtin and the cnns:
# total time (inference included) against N.
want cnn-scale && run impact-scale --scene scenes/impact.toml --warmstarts "builtin,cnn$(fam impact)" --seeds 1 $CNNSCALE \
  --scale-oracle-max 0 --no-oracle --max-sweeps 10000
echo "families-bench: reports under $OUT/*/report.md and $OUT/*/scale.md"
