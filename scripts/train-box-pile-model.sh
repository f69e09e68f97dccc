#!/usr/bin/env bash
# Trains models/box_pile.h5, the cnn warm start for scenes/box_pile.toml that sees the bodies'
# shapes (docs/learning.md "Shape channels"), and its ablation without the
# shape channels on the same data, then benchmarks both on held-out seeds. The pipeline:
#
#   1. deepcontact generate: SIMS box_pile simulations (60 boxes 1.5 x 1.0 m, STEPS steps each)
#      with scene seeds 1000..1000+SIMS-1 — disjoint from the evaluation seeds 1..EVAL — with
#      the residual channels of the default model plus coverage, orient_c, orient_s.
#   2. research/scripts/drop-feature-channels.py: the same file without the three shape channels (every
#      sample, label, body and contact identical), so the two models differ only in their input.
#   3. deepcontact train, twice with identical options (those of scripts/train-default-model.sh:
#      unet-fast, residual, asinh label scale 10, contact weight 10, dead zone DEADZONE N):
#      models/box_pile.h5 (with shapes) and $BUILD/data/box_pile-noshape.h5 (without).
#   4. deepcontact bench on scenes/box_pile.toml, seeds 1..EVAL: zero, builtin and both models
#      on the same LCPs (paired), report in $BUILD/data/box_pile-bench/.
#
# THREADS is fixed (a training is bit-reproducible only for the same thread count). Environment
# overrides: BUILD (default build), SIMS, STEPS, EPOCHS, EVERY, THREADS, DEADZONE, EVAL, ARCH,
# OUT (the model with shapes); SKIP_BENCH=1 stops after training. SCENE picks another scene
# (NAME, default its file name, prefixes every output; OUT then defaults to models/NAME.h5 —
# pass OUT=build/data/NAME.h5 to keep an experiment out of models/).
set -euo pipefail
cd "$(dirname "$0")/.."

BUILD=${BUILD:-build}
DC="$BUILD/bin/deepcontact"
SIMS=${SIMS:-20}
STEPS=${STEPS:-400}
EPOCHS=${EPOCHS:-10}
EVERY=${EVERY:-3}
THREADS=${THREADS:-2}
DEADZONE=${DEADZONE:-20}
EVAL=${EVAL:-4}
ARCH=${ARCH:-models/arch/unet-fast.toml}
SCENE=${SCENE:-scenes/box_pile.toml}
NAME=${NAME:-$(basename "$SCENE" .toml)}
SHAPE=coverage,orient_c,orient_s
CHANNELS=mass,vx,vy,omega,contact_density,lambda_prev_n,lambda_prev_t,vrel_n,vrel_t,gap,$SHAPE
GRID=poly6:0.5:0.5  # the default model's grid (docs/learning.md "Default model")
DATADIR="$BUILD/data"
DATA="$DATADIR/$NAME-train-s1000-m$SIMS-t$STEPS.h5"
DATA_NOSHAPE="$DATADIR/$NAME-train-s1000-m$SIMS-t$STEPS-noshape.h5"
OUT=${OUT:-models/$NAME.h5}
OUT_NOSHAPE="$DATADIR/$NAME-noshape.h5"

[ -x "$DC" ] || { echo "train-box-pile-model.sh: $DC not found; build it first" >&2; exit 1; }
mkdir -p "$DATADIR" "$(dirname "$OUT")"

t0=$(date +%s)
if [ -f "$DATA" ]; then
  echo "== data set $DATA exists; reusing it"
else
  RESUME=()
  [ -f "$DATA.partial" ] && RESUME=(--resume)
  echo "== generating $SIMS $NAME simulations (seeds 1000..$((1000 + SIMS - 1)), $STEPS steps) into $DATA"
  "$DC" generate --scene "$SCENE" --sims "$SIMS" --seed 1000 --steps "$STEPS" --threads "$THREADS" \
    --grid "$GRID" --channels "$CHANNELS" --out "$DATA" "${RESUME[@]}"
fi
[ -f "$DATA_NOSHAPE" ] || /usr/bin/python3 research/scripts/drop-feature-channels.py "$DATA" "$DATA_NOSHAPE" "$SHAPE"
t1=$(date +%s)

# --shuffle-buffer 8192: the whole training split in memory, the order the shipped models were
# trained with (docs/learning.md "Sample order and memory").
train() {  # data, model
  echo "== training $2 on $1"
  "$DC" train --data "$1" --out "$2" --force \
    --arch "$ARCH" --residual --label-scale 10 --contact-weight 10 --deadzone "$DEADZONE" \
    --epochs "$EPOCHS" --every "$EVERY" --batch 32 --lr 5e-3 --momentum 0.9 --weight-decay 1e-4 \
    --val 0.2 --seed 1 --threads "$THREADS" --no-plot --shuffle-buffer 8192
  mv -f "$2.loss.csv" "$DATADIR/$(basename "$2" .h5).loss.csv"
}
train "$DATA" "$OUT"
train "$DATA_NOSHAPE" "$OUT_NOSHAPE"
t2=$(date +%s)
echo "== generation $((t1 - t0)) s, training $((t2 - t1)) s (wall)"

[ -n "${SKIP_BENCH:-}" ] && exit 0
echo "== bench on $SCENE, held-out seeds 1..$EVAL"
"$DC" bench --scene "$SCENE" --seeds "1..$EVAL" --steps "$STEPS" \
  --warmstarts "zero,builtin,cnn:$OUT,cnn:$OUT_NOSHAPE" --out "$DATADIR/$NAME-bench"
