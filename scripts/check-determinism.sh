#!/usr/bin/env bash
# The determinism check of docs/reproducibility.md: the same scene must give the
# same final state, bit for bit, with the native build (-march=native, what `make build`
# and `make test` produce) and with a portable build (-DDC_NATIVE=OFF, x86-64 baseline:
# SSE2, no FMA, no AVX). The portable binary is also run with glibc's libm forced to its
# non-FMA, non-AVX2 code paths (GLIBC_TUNABLES), which is what a CPU without FMA would
# execute: glibc's exp/log/pow give different last bits there.
#
#   scripts/check-determinism.sh [NATIVE_BUILD_DIR]      (default: build)
#
# Environment: PORTABLE_BUILD (default build-portable), JOBS (default: nproc), CMAKE_ARGS
# (passed to the portable configure, e.g. -DCMAKE_CXX_COMPILER_LAUNCHER=ccache).
# Builds only the `deepcontact` target of the portable tree (no tests, no benchmarks).
# Prints the CPU model and a table of hashes; exits 1 if any hash differs.
set -euo pipefail
cd "$(dirname "$0")/.."
NATIVE=${1:-build}
PORTABLE=${PORTABLE_BUILD:-build-portable}
JOBS=${JOBS:-$(nproc)}
NATIVE_DC="$NATIVE/bin/deepcontact"
PORTABLE_DC="$PORTABLE/bin/deepcontact"
NO_FMA_LIBM="glibc.cpu.hwcaps=-AVX2,-FMA"

if [[ ! -x "$NATIVE_DC" ]]; then
  echo "check-determinism: $NATIVE_DC not found; build the native tree first (make build)" >&2
  exit 2
fi
if grep -q '^DC_NATIVE:BOOL=OFF' "$NATIVE/CMakeCache.txt" 2>/dev/null; then
  echo "check-determinism: WARNING: $NATIVE is a -DDC_NATIVE=OFF build; the check compares two portable builds" >&2
fi
echo "check-determinism: CPU: $(lscpu | sed -n 's/^Model name: *//p' | head -1)"

t0=$(date +%s)
# shellcheck disable=SC2086  # CMAKE_ARGS is a list of arguments
cmake -S . -B "$PORTABLE" -DCMAKE_BUILD_TYPE=Release -DDC_NATIVE=OFF -DDC_TESTS=OFF -DDC_BENCHMARKS=OFF \
  ${CMAKE_ARGS:-} > /dev/null
cmake --build "$PORTABLE" -j "$JOBS" --target deepcontact > "$PORTABLE/check-determinism-build.log" 2>&1 || {
  tail -n 30 "$PORTABLE/check-determinism-build.log" >&2
  echo "check-determinism: the portable build failed (log: $PORTABLE/check-determinism-build.log)" >&2
  exit 1
}
t1=$(date +%s)
echo "check-determinism: portable build of deepcontact: $((t1 - t0)) s"

# name | simulate arguments. Together they cover friction and μ = 0, generated and explicit
# bodies, other sizes and box, fixed sweeps and tolerance mode, the builtin, sph and copy
# warm starters, the Newton oracle (box_newton) as the stepping solver, the default solver
# pgs-colored (its kernel is chosen at run time in every build; the rows below the table
# compare its scalar, AVX2 and AVX-512 kernels in both builds) and pgs, the Morton body
# numbering, and the shape scenes (boxes, ellipses, polygons, static and kinematic bodies).
scenes=(
  "seed (600 steps, 3000 sweeps)|"
  "frictionless (mu = 0)|--scene scenes/frictionless.toml --steps 200"
  "column (explicit bodies)|--scene scenes/column.toml --steps 200"
  "generate-like (73 x r=0.6 m, 20 m box, sph, tol)|--set bodies.count=73 --set bodies.radius=0.6 --set bodies.seed=7 \
--set world.width=20.0 --set world.height=20.0 --set bodies.mean=[10.0,8.0] --set bodies.sigma=3.0 \
--set solver.tolerance=0.01 --steps 150 --warmstart sph"
  "small (newton solver, copy)|--scene scenes/small.toml --set solver.name=newton --warmstart copy"
  "seed, pgs (300 steps)|--set solver.name=pgs --steps 300"
  # [bodies] order = "morton": the generated bodies renumbered by integer Morton codes.
  "seed, bodies in Morton order (300 steps)|--set bodies.order=morton --steps 300"
  # Shape scenes: polygon SAT + clipping, libccd ellipse pairs with the normal
  # polish, static and kinematic bodies; their rotations use det_sincos (no libm).
  "box_pile (60 boxes, two-point manifolds)|--scene scenes/box_pile.toml --steps 200"
  "mixed (ellipses, polygons, circles)|--scene scenes/mixed.toml --steps 200"
  "hopper (pentagons, static plates)|--scene scenes/hopper.toml --steps 150"
  "drum (kinematic pivoted boxes)|--scene scenes/drum.toml --steps 150"
)

fail=0
printf '%-50s %-17s %-17s %-17s\n' "scene" "native" "portable" "portable+no-FMA libm"
for entry in "${scenes[@]}"; do
  name=${entry%%|*}
  read -r -a args <<< "${entry#*|}"
  # A run that fails shows as "exit N" in its column (and fails the check) instead of ending
  # the script without a word.
  hn=$("$NATIVE_DC" simulate "${args[@]}" --hash) || hn="exit $?"
  hp=$("$PORTABLE_DC" simulate "${args[@]}" --hash) || hp="exit $?"
  hl=$(GLIBC_TUNABLES=$NO_FMA_LIBM "$PORTABLE_DC" simulate "${args[@]}" --hash) || hl="exit $?"
  mark=""
  if [[ "$hn" != "$hp" || "$hn" != "$hl" ]]; then
    mark="  <-- DIFFERS"
    fail=1
  fi
  printf '%-50s %-17s %-17s %-17s%s\n' "$name" "$hn" "$hp" "$hl" "$mark"
done
# pgs-colored's kernels (pgs-colored:1:<kernel>; a kernel this CPU lacks is skipped) must give
# the hash of the scalar one, in both builds: the portable build chooses its AVX2 and AVX-512
# kernels at run time too, with Eigen's buffers aligned to 16 bytes only.
ref=""
for build in native portable; do
  dc=$NATIVE_DC
  [[ $build == portable ]] && dc=$PORTABLE_DC
  for kernel in scalar avx2 avx512; do
    h=$("$dc" simulate --set "solver.name=pgs-colored:1:$kernel" --steps 300 --hash 2>/dev/null) || {
      rc=$?
      if ((rc == 1)); then
        echo "seed, pgs-colored $kernel kernel ($build): not available on this CPU"
      else
        echo "seed, pgs-colored $kernel kernel ($build): CRASHED (exit $rc)  <-- FAILS"
        fail=1
      fi
      continue
    }
    [[ -n "$ref" ]] || ref=$h
    mark=""
    if [[ "$h" != "$ref" ]]; then
      mark="  <-- DIFFERS from the scalar kernel"
      fail=1
    fi
    printf '%-50s %-17s%s\n' "seed, pgs-colored $kernel kernel ($build)" "$h" "$mark"
  done
done
echo "check-determinism: hashes computed in $(($(date +%s) - t1)) s"
if ((fail)); then
  echo "check-determinism: FAILED: the builds (or pgs-colored's kernels) give different trajectories" \
       "(docs/reproducibility.md)" >&2
  exit 1
fi
echo "check-determinism: OK: every scene has the same final-state hash on all builds"
