#!/usr/bin/env bash
# Retrains the shipped default CNN model, models/default.h5 (docs/learning.md "Default model").
# `make model` runs this after building. The pipeline, exactly:
#
#   1. deepcontact generate: M seed-scene simulations (50..100 circles, 600 steps each) with
#      scene seeds 1000..1000+M-1 — disjoint from the bench's evaluation seeds 1..8 — with the
#      residual feature channels (the builtin warm start, relative velocity and gap at the
#      contacts on the grid; docs/learning.md "Residual models").
#   2. deepcontact train: the cheap U-Net models/arch/unet-fast.toml (stride-2 first layer, a
#      31 -> 16 -> 8 -> 4 U-Net and a 1x1 head at 61 x 61: cheap to infer) as a RESIDUAL model
#      (learns λ* − λ_prev, asinh-compressed with scale 10, loss weight 11 at contact nodes,
#      corrections below DEADZONE N ignored at inference) on
#      every 4th step of each simulation (consecutive steps are nearly identical), validation =
#      20 % of the simulations.
#
# Sized for a 2-core machine: 32 x 600 steps = 19176 samples, of which 4795 are used; on an
# idle 2-core box about 1.5 min of generation and a few seconds per epoch of training
# (docs/learning.md "Default model" has the measured times). ARCH overrides the architecture
# (the model shipped before unet-fast was ARCH=models/arch/unet-deep-slim.toml).
# THREADS is fixed (not nproc) because a training is bit-reproducible only for the same
# thread count; the data set does not depend on it. Environment overrides: BUILD (build dir,
# default build), SIMS, EPOCHS, EVERY, THREADS, DEADZONE, ARCH; DATA (the data set path), OUT (the model).
set -euo pipefail
cd "$(dirname "$0")/.."

BUILD=${BUILD:-build}
DC="$BUILD/bin/deepcontact"
SIMS=${SIMS:-32}
EPOCHS=${EPOCHS:-5}
EVERY=${EVERY:-4}
THREADS=${THREADS:-2}
# The dead zone [N] of the residual correction, chosen on validation seeds 500..501 (neither
# training nor evaluation seeds; docs/learning.md "Default model").
DEADZONE=${DEADZONE:-20}
ARCH=${ARCH:-models/arch/unet-fast.toml}
DATA=${DATA:-$BUILD/data/default-train-residual-s1000-m$SIMS.h5}
CHANNELS=mass,vx,vy,omega,contact_density,lambda_prev_n,lambda_prev_t,vrel_n,vrel_t,gap
# h = d = 0.5, not the sph starter's h = 0.355: the read-back divides by the kernel-weight
# field, which h = 0.355 leaves at ~1e-9 of its peak near cell centres (docs/learning.md).
GRID=poly6:0.5:0.5
OUT=${OUT:-models/default.h5}

[ -x "$DC" ] || { echo "train-default-model.sh: $DC not found; run 'make build' first" >&2; exit 1; }
mkdir -p "$(dirname "$DATA")" "$(dirname "$OUT")"

start=$(date +%s)
if [ -f "$DATA" ]; then
  echo "== data set $DATA exists; reusing it"
elif [ -f "$DATA.partial" ]; then
  echo "== resuming the interrupted data set $DATA.partial"
  "$DC" generate --sims "$SIMS" --seed 1000 --threads "$THREADS" --grid "$GRID" --channels "$CHANNELS" --out "$DATA" --resume
else
  echo "== generating $SIMS simulations (seeds 1000..$((1000 + SIMS - 1))) into $DATA"
  "$DC" generate --sims "$SIMS" --seed 1000 --threads "$THREADS" --grid "$GRID" --channels "$CHANNELS" --out "$DATA"
fi
gen_done=$(date +%s)

# --shuffle-buffer 8192 keeps the whole training split (~3,900 samples, ~760 MB) in memory and
# so visits it in the full Fisher-Yates order models/default.h5 was trained with; the default
# buffer (2048) would stream it in the buffered order (docs/learning.md "Sample order and memory").
RESUME=()
[ -f "$OUT.ckpt" ] && RESUME=(--resume) && echo "== resuming the interrupted training from $OUT.ckpt"
echo "== training $OUT"
"$DC" train --data "$DATA" --out "$OUT" --force "${RESUME[@]}" \
  --arch "$ARCH" --residual --label-scale 10 --contact-weight 10 --deadzone "$DEADZONE" \
  --epochs "$EPOCHS" --every "$EVERY" --batch 32 --lr 5e-3 --momentum 0.9 --weight-decay 1e-4 \
  --val 0.2 --seed 1 --threads "$THREADS" --shuffle-buffer 8192
end=$(date +%s)
# The loss curve belongs next to the data set (a build output), not in the repository.
LOSS="$(dirname "$DATA")/$(basename "$OUT" .h5).loss"
mv -f "$OUT.loss.csv" "$LOSS.csv"
if [ -f "$OUT.loss.png" ]; then mv -f "$OUT.loss.png" "$LOSS.png"; fi
echo "== done: generation $((gen_done - start)) s, training $((end - gen_done)) s -> $OUT" \
     "(loss curve: $LOSS.csv/.png)"
