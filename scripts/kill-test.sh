#!/usr/bin/env bash
# Kill test (docs/robustness.md "Kills"): SIGKILL at random instants of generate, train,
# bench and simulate, SIGTERM, and two concurrent `generate --resume` with HDF5's file
# locking off. Counts, over all trials:
#   lost      committed work (a simulation reported "completed", a finished output) missing
#             or changed afterwards
#   unreadable an output under its final name that does not open and read whole
#   crashes   a resume / rerun after the kill that does not exit 0 (or 1 for a refused
#             concurrent run)
#   mixes     a data set, model or result that differs from the uninterrupted reference, or
#             two concurrent runs that both wrote
# and exits 1 unless all four are 0. Not part of `make test` (minutes of CPU); CI runs
# KILL_TEST_SHORT=1 (a few kills of each).
# Usage: [KILLS_GENERATE=100] [KILLS_OTHER=20] [KILL_TEST_SHORT=1] scripts/kill-test.sh [BUILD_DIR]
set -uo pipefail
cd "$(dirname "$0")/.."
BUILD=${1:-build}
case $BUILD in /*) DC=$BUILD/bin/deepcontact ;; *) DC=$PWD/$BUILD/bin/deepcontact ;; esac
PY=/usr/bin/python3
[ -x "$DC" ] || { echo "kill-test: $DC not built" >&2; exit 1; }
if [ "${KILL_TEST_SHORT:-0}" = 1 ]; then KG=${KILLS_GENERATE:-8}; KO=${KILLS_OTHER:-2}; else KG=${KILLS_GENERATE:-100}; KO=${KILLS_OTHER:-20}; fi
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
export OMP_NUM_THREADS=2
lost=0 unreadable=0 crashes=0 mixes=0
RANDOM=${KILL_TEST_SEED:-1}
t0=$SECONDS
# A random instant in [0, T) seconds (T: the reference run's wall time).
instant() { awk -v r=$RANDOM -v t="$1" 'BEGIN { printf "%.3f", r / 32768 * t }'; }
now() { date +%s.%N; }
elapsed() { awk -v a="$1" -v b="$(now)" 'BEGIN { printf "%.3f", b - a }'; }
same() { $PY scripts/h5_compare.py "$@" >/dev/null 2>&1; }
# Every HDF5 file given opens and every dataset reads whole (virtual ones through their shards).
readable() {
  $PY - "$@" <<'PYEOF' >/dev/null 2>&1
import sys, h5py
for p in sys.argv[1:]:
    with h5py.File(p, "r") as f:
        f.visititems(lambda n, o: o[()] if isinstance(o, h5py.Dataset) else None)
PYEOF
}

# ---- generate: the writer-bound setting (150 steps of small scenes) ------------------
FAM=(--set world.width=12 --set world.height=12 --set bodies.mean=[6.0,6.0] --set bodies.sigma=2.0 --seed 5
     --count 10..14 --steps 150 --sims 8)
s=$(now); "$DC" generate "${FAM[@]}" --threads 1 --out "$work/ref.h5" >/dev/null || exit 1; T=$(elapsed "$s")
echo "kill-test: generate reference ${T} s"
for ((i = 0; i < KG; i++)); do
  out=$work/g.h5; rm -rf "$out" "$out".*
  "$DC" generate "${FAM[@]}" --threads $((1 + i % 2)) --log-completed --out "$out" >/dev/null 2>"$work/g.log" &
  pid=$!
  sleep "$(instant "$T")"
  kill -KILL $pid 2>/dev/null
  wait $pid 2>/dev/null
  # The shards reported committed, with their inode and mtime: resume must not touch them.
  committed=$(sed -n 's/^completed \([0-9]*\) .*/\1/p' "$work/g.log")
  before=""
  for c in $committed; do
    f=$(ls "$out".shards/*/"$(printf 'sim-%06d.h5' "$c")" 2>/dev/null)
    if [ -z "$f" ]; then lost=$((lost + 1)); continue; fi
    readable "$f" || unreadable=$((unreadable + 1))
    before+="$(stat -c '%n %i %Y' "$f")"$'\n'
  done
  # Killed before the run was set up (no OUT.partial): a fresh run; else resume.
  again=(--resume); [ -f "$out.partial" ] || again=()
  if [ ! -f "$out" ] || [ -f "$out.partial" ]; then
    "$DC" generate "${FAM[@]}" --threads 2 "${again[@]}" --out "$out" >/dev/null 2>"$work/r.log" || { crashes=$((crashes + 1)); cat "$work/r.log"; }
  fi
  for c in $committed; do
    f=$(ls "$out".shards/*/"$(printf 'sim-%06d.h5' "$c")" 2>/dev/null)
    [ -n "$f" ] && grep -qxF "$(stat -c '%n %i %Y' "$f")" <<<"$before" || lost=$((lost + 1))
  done
  readable "$out" || unreadable=$((unreadable + 1))
  same "$work/ref.h5" "$out" --ignore '^/shards' || { mixes=$((mixes + 1)); echo "kill-test: generate kill $i: differs"; }
done
echo "kill-test: generate: $KG SIGKILLs (lost $lost, unreadable $unreadable, crashes $crashes, mixes $mixes)"

# SIGTERM: exit 143 (or 0 when it finished first), then resume to the reference.
out=$work/t.h5; rm -rf "$out" "$out".*
"$DC" generate "${FAM[@]}" --threads 1 --out "$out" >/dev/null 2>&1 &
pid=$!; sleep "$(instant "$T")"; kill -TERM $pid 2>/dev/null; wait $pid; rc=$?
[ $rc = 143 ] || [ $rc = 0 ] || { crashes=$((crashes + 1)); echo "kill-test: SIGTERM: exit $rc"; }
again=(--resume); [ -f "$out.partial" ] || again=()
if [ ! -f "$out" ] || [ -f "$out.partial" ]; then
  "$DC" generate "${FAM[@]}" "${again[@]}" --out "$out" >/dev/null 2>&1 || crashes=$((crashes + 1))
fi
same "$work/ref.h5" "$out" --ignore '^/shards' || mixes=$((mixes + 1))
echo "kill-test: generate: SIGTERM exit $rc, resumed"

# Two concurrent resumes with HDF5's locking off: one is refused by OUT.lock, one completes.
out=$work/c.h5; rm -rf "$out" "$out".*
"$DC" generate "${FAM[@]}" --threads 1 --log-completed --out "$out" >/dev/null 2>"$work/c.log" &
pid=$!; until grep -q "completed 1 " "$work/c.log" 2>/dev/null || ! kill -0 $pid 2>/dev/null; do sleep 0.02; done
kill -KILL $pid 2>/dev/null; wait $pid 2>/dev/null
HDF5_USE_FILE_LOCKING=FALSE "$DC" generate "${FAM[@]}" --threads 1 --resume --out "$out" >/dev/null 2>"$work/c1.log" & p1=$!
HDF5_USE_FILE_LOCKING=FALSE "$DC" generate "${FAM[@]}" --threads 1 --resume --out "$out" >/dev/null 2>"$work/c2.log" & p2=$!
wait $p1; r1=$?; wait $p2; r2=$?
if [ $((r1 + r2)) != 1 ]; then
  # Both 0 would mean two writers; the lock lets at most one run.
  if [ $r1 = 0 ] && [ $r2 = 0 ]; then mixes=$((mixes + 1)); else crashes=$((crashes + 1)); fi
  echo "kill-test: concurrent resumes exited $r1 and $r2"; cat "$work/c1.log" "$work/c2.log"
fi
same "$work/ref.h5" "$out" --ignore '^/shards' || mixes=$((mixes + 1))
echo "kill-test: generate: concurrent resumes exited $r1 / $r2 ($(cat "$work/c1.log" "$work/c2.log" | head -c 160))"

# ---- train: SIGKILL, then --resume (or a fresh run) equals the uninterrupted model -----
TRAIN=(train --data "$work/ref.h5" --epochs 3 --every 4 --batch 16 --threads 1 --no-plot)
s=$(now); "$DC" "${TRAIN[@]}" --out "$work/mref.h5" >/dev/null || exit 1; T=$(elapsed "$s")
for ((i = 0; i < KO; i++)); do
  out=$work/m.h5; rm -f "$out" "$out".*
  "$DC" "${TRAIN[@]}" --out "$out" >/dev/null 2>&1 & pid=$!
  sleep "$(instant "$T")"; kill -KILL $pid 2>/dev/null; wait $pid 2>/dev/null
  for f in "$out" "$out.ckpt"; do [ -f "$f" ] && { readable "$f" || unreadable=$((unreadable + 1)); }; done
  if [ -f "$out.ckpt" ]; then again=(--resume); else again=(--force); fi
  "$DC" "${TRAIN[@]}" --out "$out" "${again[@]}" >/dev/null 2>"$work/r.log" || { crashes=$((crashes + 1)); cat "$work/r.log"; }
  same "$work/mref.h5" "$out" --ignore '(seconds|date|time)' || mixes=$((mixes + 1))
done
echo "kill-test: train: $KO SIGKILLs (totals so far: lost $lost, unreadable $unreadable, crashes $crashes, mixes $mixes)"

# ---- bench: a killed run leaves DIR absent, complete, or holding only its partial-run-*
# folder (the report is moved in only when complete); a rerun succeeds ------------------
BENCH=(bench --warmstarts zero,builtin --seeds 1 --steps 30 --sweeps 50 --set world.width=12 --set world.height=12
       --set bodies.count=12 --set bodies.mean=[6.0,6.0] --set bodies.sigma=2.0)
s=$(now); "$DC" "${BENCH[@]}" --out "$work/bref" >/dev/null || exit 1; T=$(elapsed "$s")
for ((i = 0; i < KO; i++)); do
  out=$work/b; rm -rf "$out" "$out".*
  "$DC" "${BENCH[@]}" --out "$out" >/dev/null 2>&1 & pid=$!
  sleep "$(instant "$T")"; kill -KILL $pid 2>/dev/null; wait $pid 2>/dev/null
  if [ -e "$out" ] && [ -n "$(ls "$out" | grep -v '^partial-run-')" ]; then
    { readable "$out/results.h5" && $PY -c "import json,sys; json.load(open(sys.argv[1]))" "$out/summary.json"; } \
      || { unreadable=$((unreadable + 1)); echo "kill-test: bench kill $i: incomplete $out"; }
  fi
  "$DC" "${BENCH[@]}" --out "$out" >/dev/null 2>"$work/r.log" || { crashes=$((crashes + 1)); cat "$work/r.log"; }
done
echo "kill-test: bench: $KO SIGKILLs (totals so far: lost $lost, unreadable $unreadable, crashes $crashes, mixes $mixes)"

# ---- simulate: OUT stays the earlier complete trajectory until the new one is complete ---
SIM=(simulate --set bodies.count=40 --set bodies.mean=[15.0,4.0] --set bodies.sigma=3.0)
"$DC" "${SIM[@]}" --steps 50 --out "$work/early.h5" >/dev/null || exit 1
s=$(now); "$DC" "${SIM[@]}" --steps 600 --out "$work/sref.h5" >/dev/null || exit 1; T=$(elapsed "$s")
for ((i = 0; i < KO; i++)); do
  out=$work/s.h5; rm -f "$out" "$out".*; cp "$work/early.h5" "$out"
  "$DC" "${SIM[@]}" --steps 600 --out "$out" >/dev/null 2>&1 & pid=$!
  sleep "$(instant "$T")"; kill -KILL $pid 2>/dev/null; wait $pid 2>/dev/null
  readable "$out" || unreadable=$((unreadable + 1))
  cmp -s "$out" "$work/early.h5" || same "$work/sref.h5" "$out" --ignore 'profile' || { lost=$((lost + 1)); echo "kill-test: simulate kill $i: OUT is neither"; }
  "$DC" "${SIM[@]}" --steps 600 --out "$out" >/dev/null 2>"$work/r.log" || { crashes=$((crashes + 1)); cat "$work/r.log"; }
done
echo "kill-test: simulate: $KO SIGKILLs"

echo "kill-test: $KG generate + $KO each train/bench/simulate SIGKILLs, SIGTERM, concurrent resumes in $((SECONDS - t0)) s:" \
     "lost $lost, unreadable $unreadable, crashes $crashes, mixes $mixes"
[ $((lost + unreadable + crashes + mixes)) = 0 ]
