#!/usr/bin/env bash
# The robustness stage of CI (docs/robustness.md), meant to run after `make test` on a clean clone:
#   1. the whole test suite once under AddressSanitizer + UndefinedBehaviorSanitizer
#      (`make sanitize`: RelWithDebInfo build in build-asan/, then ctest);
#   2. every libFuzzer harness for FUZZ_SECONDS seconds (default 60) via scripts/fuzz.sh.
# Prints the wall time of each part and exits non-zero if either found a problem.
#
#   scripts/ci-extra.sh                      # both parts
#   FUZZ_SECONDS=30 scripts/ci-extra.sh      # shorter fuzzing
#   SKIP_SANITIZE=1 / SKIP_FUZZ=1            # one part only
# Environment: JOBS (build/test parallelism, default 2).
set -uo pipefail

ROOT=$(cd "$(dirname "$0")/.." && pwd)
JOBS=${JOBS:-2}
FUZZ_SECONDS=${FUZZ_SECONDS:-60}
now() { date +%s; }

# Defects inside libhdf5 that corrupt files trigger (regression inputs in tests/fuzz/regressions)
# are suppressed for the sanitizers; see tests/fuzz/{asan,lsan}.supp.
export ASAN_OPTIONS="suppressions=$ROOT/tests/fuzz/asan.supp${ASAN_OPTIONS:+:$ASAN_OPTIONS}"
export LSAN_OPTIONS="suppressions=$ROOT/tests/fuzz/lsan-suite.supp${LSAN_OPTIONS:+:$LSAN_OPTIONS}"
# UBSan: print a stack for every report (the build already aborts on the first one).
export UBSAN_OPTIONS="print_stacktrace=1${UBSAN_OPTIONS:+:$UBSAN_OPTIONS}"

rc_san=0 rc_fuzz=0 t_san=0 t_fuzz=0
t0=$(now)
if [ -z "${SKIP_SANITIZE:-}" ]; then
  echo "ci-extra: make sanitize (ASan + UBSan build and ctest, -j$JOBS)"
  make -C "$ROOT" sanitize JOBS="$JOBS" || rc_san=$?
fi
t1=$(now)
t_san=$((t1 - t0))
if [ -z "${SKIP_FUZZ:-}" ]; then
  echo "ci-extra: scripts/fuzz.sh $FUZZ_SECONDS"
  # fuzz.sh sets its own (precise) suppressions.
  ASAN_OPTIONS= LSAN_OPTIONS= JOBS=$JOBS "$ROOT/scripts/fuzz.sh" "$FUZZ_SECONDS" || rc_fuzz=$?
fi
t2=$(now)
t_fuzz=$((t2 - t1))

echo
echo "ci-extra: sanitize $( [ -n "${SKIP_SANITIZE:-}" ] && echo skipped || { [ $rc_san -eq 0 ] && echo passed || echo "FAILED ($rc_san)"; }) in ${t_san}s;" \
     "fuzz $( [ -n "${SKIP_FUZZ:-}" ] && echo skipped || { [ $rc_fuzz -eq 0 ] && echo clean || echo "FOUND PROBLEMS ($rc_fuzz)"; }) in ${t_fuzz}s;" \
     "total $((t2 - t0))s"
[ $rc_san -eq 0 ] && [ $rc_fuzz -eq 0 ]
