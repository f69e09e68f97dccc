#!/bin/sh
# Trains models/<family>.h5, a warm start trained THROUGH PGS for one scene family
# (docs/design.md §8.5; docs/learning.md "Training through PGS", docs/research/family-models.md):
# the shipped residual cnn (models/default.h5, trained on the seed scene's 61 x 61 grid) is the
# --init model; being fully convolutional it runs on the family's own grid (same d, h, kernel,
# channels), and train --loss pgs-* fine-tunes it on the family's LCPs.
#
#   scripts/train-family-model.sh FAMILY [BUILD_DIR]     (FAMILY: impact, pour, polydisperse, ...)
#
# Environment (defaults in brackets): SIMS [6] training simulations, seeds 1000.. (the
# families' evaluation seeds are 1..4: disjoint); STEPS [260 for impact and pour (the impact
# happens at ~step 217; the bench windows end at 260), 200 for polydisperse and drum, else the scene's]; EVERY [4] (every
# k-th step becomes a sample); LOSS [pgs-distance]; UNROLL [100]; EPOCHS and LR [impact: 4
# at 0.5, pour: 8 at 0.1, else 6 at 0.1: the shipped models' settings, chosen by validation
# objective among 2-3 short runs, docs/research.md; mixed: 30 at 0.02]; CLIP [0.05]; TIME [400] s of training
# at most; DEADZONE [0]; THREADS [impact 2, else 1: training bits depend on the thread
# count]; INIT [models/default.h5]; CH [the shipped model's 10 channels; must be --init's
# channels, e.g. ...,coverage,orient_c,orient_s with INIT=models/box_pile.h5 for shapes];
# FIRST [0: the first step kept as a sample, train --first-step]; GAIN [0; 1 = train a gain model from the residual --init, docs/learning.md "Gain models"];
# FIELD_ITER [100: CGLS iterations of the target field with LOSS=pgs-field];
# OUT [models/FAMILY.h5].
case "$1" in
  impact) : "${STEPS:=260}" "${EPOCHS:=4}" "${LR:=0.5}" "${THREADS:=2}" ;;
  pour) : "${STEPS:=260}" "${EPOCHS:=8}" "${LR:=0.1}" "${THREADS:=1}" ;;
  polydisperse|drum) : "${STEPS:=200}" ;;  # the bench windows end at step 200 (docs/research.md)
  # The mixed-shape pile: the shape channels and the box-pile model (trained on them) as start.
  mixed) : "${STEPS:=400}" "${INIT:=models/box_pile.h5}" "${LR:=0.02}" "${EPOCHS:=30}" \
    "${CH:=mass,vx,vy,omega,contact_density,lambda_prev_n,lambda_prev_t,vrel_n,vrel_t,gap,coverage,orient_c,orient_s}" ;;
esac
set -eu
F=${1:?usage: scripts/train-family-model.sh FAMILY [BUILD_DIR]}
BUILD=${2:-build}
DC=$BUILD/bin/deepcontact
SCENE=scenes/$F.toml
[ -f "$SCENE" ] || { echo "train-family-model: $SCENE not found" >&2; exit 2; }
SIMS=${SIMS:-6}
THREADS=${THREADS:-1}
DATADIR=$BUILD/data
mkdir -p "$DATADIR"
STEPS_ARG=""
[ -n "${STEPS:-}" ] && STEPS_ARG="--steps $STEPS"
# The shipped model's grid and channels (the data set must match --init's to start from it).
CH=${CH:-mass,vx,vy,omega,contact_density,lambda_prev_n,lambda_prev_t,vrel_n,vrel_t,gap}
NCH=$(echo "$CH" | tr ',' '\n' | wc -l)
DATA=$DATADIR/$F-train-s1000-m$SIMS${STEPS:+-t$STEPS}-c$NCH.h5

# 1. Data: trajectories advanced with the PGS oracle (capped at 3000 sweeps) and the grids.
[ -f "$DATA" ] || /usr/bin/time -f "generate: %U s user %S s sys %e s wall" \
  $DC generate --scene "$SCENE" --sims "$SIMS" --seed 1000 $STEPS_ARG --grid poly6:0.5:0.5 --channels $CH \
    --oracle-sweeps 3000 --threads "$THREADS" --out "$DATA"

# 2. Through the solver, from the shipped model: minimise the distance to lambda* (or the
#    natural-map residual) after UNROLL sweeps, relative to builtin's start.
/usr/bin/time -f "train: %U s user %S s sys %e s wall" \
  $DC train --data "$DATA" --out "${OUT:-models/$F.h5}" --force --loss "${LOSS:-pgs-distance}" --unroll "${UNROLL:-100}" \
    --init "${INIT:-models/default.h5}" --epochs "${EPOCHS:-6}" --every "${EVERY:-4}" --batch 8 --lr "${LR:-0.1}" \
    --clip "${CLIP:-0.05}" --field-iterations "${FIELD_ITER:-100}" --deadzone "${DEADZONE:-0}" $([ "${GAIN:-0}" = 1 ] && echo --gain) \
    --first-step "${FIRST:-0}" --val 0.34 --seed 1 --threads "$THREADS" \
    --time-limit "${TIME:-400}"
echo "train-family-model: ${OUT:-models/$F.h5}; evaluate with research/scripts/families-bench.sh (STARTERS=...,cnn:${OUT:-models/$F.h5})"
