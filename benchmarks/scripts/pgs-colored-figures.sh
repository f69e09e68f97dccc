#!/usr/bin/env bash
# The pgs-colored figures in full (`make results PART=speed` runs a subset): the ns per row
# per sweep table (one micro_pgs run, all rows side by side: pgs, pgs-colored's AVX-512, AVX2 and
# scalar kernels, the scalar reference loop), 1 vs 2 threads on the 10,000-body pile, the
# colouring cost, Box2D 2.4.1 vs ours on the seed scene (each kernel), and the bench's sweeps
# to tolerance with pgs vs pgs-colored. Usage: benchmarks/scripts/pgs-colored-figures.sh
# [build-dir] (a Release build; box2d_compare needs libbox2d-dev). Takes ~8 min.
set -euo pipefail
B=${1:-build}
cmake --build "$B" -j2 --target micro_pgs deepcontact box2d_compare
echo "== ns per row per sweep (pgs, pgs-colored SIMD/scalar, scalar reference loop), colouring cost"
"$B"/bin/micro_pgs --benchmark_filter='BM_(PgsMatrixFree|PgsBaseline|PgsColored)/bodies:(100|1000|10000)/sweeps:(1|200)/order:0|SeedScenePgs(Baseline|Colored|ColoredAvx2|ColoredScalar)?$|ContactColoring' \
  --benchmark_min_time=0.2
echo "== 1 vs 2 threads, 10,000-body pile (real time, and CPU of the process / of the calling thread, per solve of 100 sweeps)"
OMP_WAIT_POLICY=passive "$B"/bin/micro_pgs --benchmark_filter=PgsColoredThreads --benchmark_repetitions=3 --benchmark_report_aggregates_only=true
echo "== Box2D 2.4.1 vs ours, seed scene (600 steps, 3000 velocity iterations)"
"$B"/bin/box2d_compare --solver pgs
for k in avx512 avx2 scalar; do "$B"/bin/box2d_compare --solver "pgs-colored:1:$k" --skip-box2d || true; done
echo "== sweeps to tolerance (bench --quick), pgs vs pgs-colored"
"$B"/bin/deepcontact bench --quick --solver pgs
"$B"/bin/deepcontact bench --quick --solver pgs-colored
