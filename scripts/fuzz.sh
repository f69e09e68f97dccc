#!/usr/bin/env bash
# Builds the libFuzzer harnesses of tests/fuzz/ (clang, ASan + UBSan, in build-fuzz/) and runs
# each for SECONDS seconds (default 60), starting from its seed corpus in
# tests/fuzz/corpus/<harness>/ (read-only: new inputs go to build-fuzz/fuzz-work/).
#
#   scripts/fuzz.sh [SECONDS] [HARNESS...]      e.g. scripts/fuzz.sh 60, scripts/fuzz.sh 10 dat
#
# Prints per harness: wall time, executions (from libFuzzer's final "#N DONE" line, or its last
# status line in fork mode), exec/s, coverage, and findings: "ours" (crash-*/leak-*/timeout-*/
# oom-* artefacts in our code) and "hdf5" (crashes whose first relevant frame is inside
# libhdf5). Artefacts stay under build-fuzz/fuzz-work/<harness>/artifacts/ — turn each of ours
# into a regression test, never commit the artefact itself.
# Exit status: 0 when no harness found anything of ours, 1 otherwise, 2 when the build failed.
# Environment: JOBS (build parallelism, default 2), FUZZ_PARALLEL (harnesses run at once,
# default JOBS; each still runs SECONDS), DC_FUZZ_BUILD (build dir), FUZZ_ARGS (extra libFuzzer flags).
set -uo pipefail

SECS=${1:-60}
shift || true
ALL=(scene dat model dataset fc2d fclib)
if [ $# -gt 0 ]; then HARNESSES=("$@"); else HARNESSES=("${ALL[@]}"); fi
ROOT=$(cd "$(dirname "$0")/.." && pwd)
BUILD=${DC_FUZZ_BUILD:-$ROOT/build-fuzz}
JOBS=${JOBS:-2}
WORK=$BUILD/fuzz-work

if ! command -v clang++ >/dev/null; then
  echo "fuzz.sh: clang++ not found (apt-get install clang libclang-rt-14-dev)" >&2
  exit 2
fi
echo "fuzz.sh: building harnesses in $BUILD (-j$JOBS)"
if ! cmake -S "$ROOT" -B "$BUILD" -DDC_FUZZ=ON -DCMAKE_CXX_COMPILER=clang++ -DCMAKE_C_COMPILER=clang \
      -DDC_TESTS=OFF -DDC_BENCHMARKS=OFF -DCMAKE_BUILD_TYPE=RelWithDebInfo >"$BUILD.configure.log" 2>&1; then
  echo "fuzz.sh: configure failed, see $BUILD.configure.log" >&2
  exit 2
fi
targets=()
for h in "${HARNESSES[@]}"; do targets+=("fuzz_$h"); done
if ! cmake --build "$BUILD" -j "$JOBS" --target "${targets[@]}" >"$BUILD.build.log" 2>&1; then
  tail -30 "$BUILD.build.log" >&2
  echo "fuzz.sh: build failed, see $BUILD.build.log" >&2
  exit 2
fi

# Leaks are findings too (LeakSanitizer is on under ASan). Two defects inside libhdf5 itself
# are suppressed (tests/fuzz/*.supp explains each); everything in our code is reported.
# fast_unwind_on_malloc=0: libhdf5 has no frame pointers, so only the slow unwinder records
# allocation stacks deep enough for the suppressions to match the HDF5 function.
export ASAN_OPTIONS="suppressions=$ROOT/tests/fuzz/asan.supp:fast_unwind_on_malloc=0${ASAN_OPTIONS:+:$ASAN_OPTIONS}"
export LSAN_OPTIONS="suppressions=$ROOT/tests/fuzz/lsan.supp${LSAN_OPTIONS:+:$LSAN_OPTIONS}"
# The HDF5 harnesses run in libFuzzer's fork mode and keep going after a crash: libhdf5 1.10.8
# itself crashes on some damaged files (docs/robustness.md), and one such input must not end
# the search for crashes in OUR readers. Every crash artefact is then re-run and classified
# by its first stack frame that lies in libhdf5 or in this repository: "hdf5" (a defect inside
# the library, reported but not failing the run) or "ours" (fails the run).
classify() {  # classify BIN ARTEFACT → prints hdf5, ours, or none (does not reproduce)
  local out rc first
  out=$("$1" -rss_limit_mb=2048 -timeout=30 "$2" 2>&1)
  rc=$?
  [ "$rc" -eq 0 ] && { echo none; return; }
  # Source frames of our libraries (not the fuzz binary's own path, which ASan prints for
  # interceptors such as memcpy called from HDF5); a UBSan report names our source directly.
  first=$(grep -E '^ *#[0-9]+ |runtime error' <<<"$out" |
          grep -m1 -E "libhdf5|$ROOT/(core|sph|io|engine|warmstart|learning|cnn|bench|research|apps|tests/fuzz)/[^ ]*\.(cpp|hpp)" || true)
  if grep -q libhdf5 <<<"$first"; then echo hdf5; else echo ours; fi
}

# fuzz_one HARNESS: runs it, classifies its artefacts, writes $WORK/HARNESS/summary (its table
# row) and $WORK/HARNESS/status (non-empty when it found something of ours).
fuzz_one() {
  local h=$1 rc ours hdf5 a
  local bin=$BUILD/tests/fuzz/fuzz_$h
  corpus=$WORK/$h/corpus
  artifacts=$WORK/$h/artifacts
  log=$WORK/$h/fuzz.log
  rm -rf "$artifacts"  # findings are per run (the corpus keeps growing across runs)
  mkdir -p "$corpus" "$artifacts"
  mode=()
  case $h in model|dataset|fclib) mode=(-fork=1 -ignore_crashes=1) ;; esac
  echo "fuzz.sh: $h for ${SECS}s (log: $log)"
  t0=$(date +%s.%N)
  # -timeout: an input running > 30 s is a hang (HDF5 inputs with the slow unwinder take seconds); -rss_limit_mb: a reader allocating what the
  # file announces rather than what it holds shows up as an OOM finding.
  # shellcheck disable=SC2086
  "$bin" -max_total_time="$SECS" -timeout=30 -rss_limit_mb=2048 -print_final_stats=1 "${mode[@]}" \
    -artifact_prefix="$artifacts/" ${FUZZ_ARGS:-} "$corpus" "$ROOT/tests/fuzz/corpus/$h" >"$log" 2>&1
  rc=$?
  t1=$(date +%s.%N)
  wall=$(awk -v a="$t0" -v b="$t1" 'BEGIN { printf "%.0f", b - a }')
  done_line=$(grep -E '^#[0-9]+[[:space:]]+DONE' "$log" | tail -1)
  execs=$(sed -nE 's/^#([0-9]+)[[:space:]]+DONE.*/\1/p' <<<"$done_line")
  rate=$(sed -nE 's/.*exec\/s: ([0-9]+).*/\1/p' <<<"$done_line")
  cov=$(sed -nE 's/.*cov: ([0-9]+).*/\1/p' <<<"$done_line")
  if [ -z "$execs" ]; then  # fork mode, or stopped by a finding: the last status line
    last=$(grep -E '^#[0-9]+' "$log" | tail -1)
    execs=$(grep -oE '^#[0-9]+' <<<"$last" | tr -d '#')
    rate=$(sed -nE 's/.*exec\/s: ([0-9]+).*/\1/p' <<<"$last")
    cov=$(sed -nE 's/.*cov: ([0-9]+).*/\1/p' <<<"$last")
  fi
  ours=0 hdf5=0
  for a in "$artifacts"/crash-* "$artifacts"/leak-* "$artifacts"/timeout-* "$artifacts"/oom-*; do
    [ -e "$a" ] || continue
    case $(classify "$bin" "$a") in
      hdf5) hdf5=$((hdf5 + 1)) ;;
      ours) ours=$((ours + 1)) ;;
    esac  # "none": fork-mode artefacts that do not reproduce on their own (e.g. load timeouts)
  done
  [ ${#mode[@]} -gt 0 ] && [ "$ours" -eq 0 ] && rc=0  # fork mode exits non-zero after ignored crashes
  { [ "$rc" -ne 0 ] || [ "$ours" -ne 0 ]; } && echo 1 > "$WORK/$h/status"
  printf '%-8s %6ss %12s %8s %6s %6s %6s %s' "$h" "$wall" "${execs:-?}" "${rate:-?}" "${cov:-?}" "$ours" "$hdf5" \
    "$([ "$rc" -eq 0 ] && [ "$ours" -eq 0 ] && echo ok || echo "FOUND (exit $rc): $(grep -m1 -E 'ERROR|SUMMARY|deadly|violated' "$log" | cut -c1-80)")" > "$WORK/$h/summary"
}

# FUZZ_PARALLEL harnesses at a time (default JOBS): a libFuzzer process is single-threaded (the
# fork-mode parent only waits), so on 2 cores two harnesses run side by side, each for SECONDS
# on a core of its own: the same search as one after the other, in half the wall time.
FUZZ_PARALLEL=${FUZZ_PARALLEL:-$JOBS}
for h in "${HARNESSES[@]}"; do
  mkdir -p "$WORK/$h"
  rm -f "$WORK/$h/summary" "$WORK/$h/status"
  while [ "$(jobs -rp | wc -l)" -ge "$FUZZ_PARALLEL" ]; do wait -n; done
  fuzz_one "$h" &
done
wait
status=0
summary=()
for h in "${HARNESSES[@]}"; do
  summary+=("$(cat "$WORK/$h/summary" 2>/dev/null || echo "$h: no result")")
  { [ -s "$WORK/$h/status" ] || [ ! -s "$WORK/$h/summary" ]; } && status=1
done

echo
printf '%-8s %7s %12s %8s %6s %6s %6s %s\n' harness time executions exec/s cov ours hdf5 result
for line in "${summary[@]}"; do echo "$line"; done
exit $status
