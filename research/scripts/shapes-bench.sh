#!/usr/bin/env bash
# The bench on the shape scenes (docs/scenes.md "Shapes"): per scene a paired
# bench of the warm starters (zero, builtin, the two non-learned baselines, copy, sph — the
# oracle grid — and the shipped cnn, which runs on any box size at its own grid spacing)
# on the scene's own seeds, PGS to θ ≤ 10⁻² N with the 3000-sweep cap, report.md per scene.
#
#   research/scripts/shapes-bench.sh [BUILD_DIR] [OUT_DIR]          (defaults: build, results/shapes)
#
# Environment: SEEDS (default 1..2), STEPS (default 300: the piles fall and settle; the drum
# turns by 1.5 rad), STARTERS (default below), ONLY="box_pile mixed hopper drum".
set -euo pipefail
cd "$(dirname "$0")/../.."
BUILD=${1:-build}
OUT=${2:-results/shapes}
DC="$BUILD/bin/deepcontact"
[[ -x "$DC" ]] || { echo "shapes-bench: $DC not found (build the deepcontact target first)" >&2; exit 2; }
S=${STARTERS:-zero,builtin,builtin-extrapolate,builtin-statics,copy,sph,cnn}
ONLY=${ONLY:-"box_pile mixed hopper drum"}
mkdir -p "$OUT"
lscpu | grep 'Model name' | tee "$OUT/cpu.txt"
for scene in $ONLY; do
  cmd=("$DC" bench --scene "scenes/$scene.toml" --warmstarts "$S" --seeds "${SEEDS:-1..2}" --steps "${STEPS:-300}"
       --out "$OUT/$scene")
  echo "== $scene: ${cmd[*]}" | tee "$OUT/$scene.cmd"
  /usr/bin/time -v "${cmd[@]}" 2> >(tee "$OUT/$scene.time" >&2) | tee "$OUT/$scene.txt"
done
echo "shapes-bench: reports under $OUT/*/report.md"
