#!/bin/sh
# Reproduces models/deep.h5, the warm start trained THROUGH PGS for the deep pile
# (docs/learning.md "Training through PGS"), and the regression model it starts from,
# then evaluates both against zero and builtin on held-out seeds.
#
#   scripts/train-deep-model.sh [BUILD_DIR]      (default build/; THREADS=2)
#
# The deep pile: 300 unit circles in a 20 x 120 box (the first look at deep piles; scenes/deep.toml
# may replace the --set lines). Training seeds 1000-1007, evaluation seeds 1-2.
set -eu
BUILD=${1:-build}
THREADS=${THREADS:-2}
DC=$BUILD/bin/deepcontact
OUT=$BUILD/data
mkdir -p "$OUT"
STEPS=${STEPS:-300}
SIMS=${SIMS:-8}
DEEP="--set world.width=20 --set world.height=120 --set bodies.count=300 --set bodies.mean=[10,40] --set bodies.sigma=20"
DATA=$OUT/deep-train-s1000-m$SIMS.h5
CH=mass,vx,vy,omega,contact_density,lambda_prev_n,lambda_prev_t,vrel_n,vrel_t,gap

# 1. Data: the trajectories (advanced with the PGS oracle, capped at 3000 sweeps) and the grids.
[ -f "$DATA" ] || $DC generate --sims "$SIMS" --seed 1000 --count 300 --steps "$STEPS" $DEEP \
    --grid poly6:0.5:0.5 --channels $CH --oracle-sweeps 3000 --threads "$THREADS" --out "$DATA"

# 2. The regression model (today's loss: weighted MSE on the asinh-compressed residual grids).
$DC train --data "$DATA" --out "$OUT/deep-regression.h5" --force --arch models/arch/unet-deep-slim.toml \
    --residual --label-scale 10 --contact-weight 10 --deadzone ${REG_DEADZONE:-0} \
    --epochs ${REG_EPOCHS:-12} --every 5 --batch 16 --lr 5e-3 --val 0.25 --seed 1 --threads "$THREADS" --no-plot

# 3. Through the solver: start from the regression model, minimise log(natural-map residual
#    after K sweeps) relative to builtin's start.
#    The shipped model: 2 epochs at lr 0.5 with the gradient clipped to norm 0.02 (~190 s of
#    training under load; docs/research.md says why it is short and what it changes).
$DC train --data "$DATA" --out models/deep.h5 --force --loss pgs-residual --unroll ${UNROLL:-30} \
    --init "$OUT/deep-regression.h5" --epochs ${PGS_EPOCHS:-2} --every 5 --batch 8 --lr ${PGS_LR:-0.5} \
    --clip ${PGS_CLIP:-0.02} --val 0.25 --seed 1 --threads "$THREADS" --time-limit ${PGS_TIME:-520}

# 4. Held-out evaluation (paired: every starter on the same LCPs).
[ -n "${SKIP_BENCH:-}" ] || $DC bench $DEEP --steps "$STEPS" --seeds 1..2 --sweeps 3000 --tol 1e-2 \
    --warmstarts zero,builtin,cnn:$OUT/deep-regression.h5,cnn:models/deep.h5,sph:poly6:0.5:0.5,copy-noise:0.1 \
    --out "$OUT/deep-bench"
[ -n "${SKIP_BENCH:-}" ] || /usr/bin/python3 research/scripts/deep-eval-summary.py "$OUT/deep-bench/results.h5" 150
