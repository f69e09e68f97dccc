#!/usr/bin/env bash
# Mutation check of the test suite (docs/mutation.md): applies each physics mutation of a list
# (scripts/mutations.txt) one at a time to the source tree, rebuilds incrementally, runs ctest
# and reports whether the suite killed it (some test failed) or it survived.
#
#   scripts/mutate.sh [--list FILE] [--build DIR] [--jobs N] [--timeout SEC] [--only ID,ID]
#                     [--table FILE] [--regex R] [--no-baseline]
#
#   --list FILE    mutation list (default scripts/mutations.txt; format in its header)
#   --build DIR    configured build directory (default build; configured Release if absent)
#   --jobs N       parallel build and test jobs (default 2)
#   --timeout SEC  ctest timeout per test (default 300); the whole ctest run of one mutation
#                  is also capped at 20 × SEC
#   --only IDS     comma-separated ids to run (default: all)
#   --table FILE   also write the result table (Markdown) to FILE
#   --regex R      run only the tests matching R (ctest -R; for trying out a new entry —
#                  the recorded table runs the whole suite)
#   --no-baseline  skip the unmutated build + ctest run (it must pass, or nothing is measured)
#
# The mutated file is edited in place and ALWAYS restored (trap on exit, Ctrl-C, errors);
# the restored file gets a new modification time so that the next build recompiles it. A
# snippet that is not found exactly once stops the script before anything is changed.
# Exit status: 0 every mutation killed, 1 some survived, 2 usage/list/build errors.
set -euo pipefail

ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
LIST="$ROOT/scripts/mutations.txt"
BUILD="$ROOT/build"
JOBS=2
TIMEOUT=300
ONLY=""
TABLE=""
BASELINE=1
REGEX=()
while [[ $# -gt 0 ]]; do
  case "$1" in
    --list) LIST="$(realpath "$2")"; shift 2 ;;
    --build) BUILD="$(realpath -m "$2")"; shift 2 ;;
    --jobs) JOBS="$2"; shift 2 ;;
    --timeout) TIMEOUT="$2"; shift 2 ;;
    --only) ONLY="$2"; shift 2 ;;
    --table) TABLE="$(realpath -m "$2")"; shift 2 ;;
    --regex) REGEX=(-R "$2"); shift 2 ;;
    --no-baseline) BASELINE=0; shift ;;
    -h|--help) sed -n '2,23p' "$0"; exit 0 ;;
    *) echo "mutate.sh: unknown option '$1' (see --help)" >&2; exit 2 ;;
  esac
done
cd "$ROOT"
WORK="$(mktemp -d "${TMPDIR:-/tmp}/dc-mutate.XXXXXX")"

# ---- the list: parse, check every snippet (exactly once), apply one -------------------------
# One Python helper does the text work; bash does the orchestration.
helper() {
  python3 - "$@" <<'PY'
import sys, pathlib
cmd, listfile = sys.argv[1], sys.argv[2]
entries, cur = [], {}
for lineno, line in enumerate(pathlib.Path(listfile).read_text().splitlines(), 1):
    if line.startswith('#'):
        continue
    if not line.strip():
        if cur: entries.append(cur); cur = {}
        continue
    key, sep, val = line.partition(':')
    if not sep or key not in ('id', 'file', 'find', 'replace', 'why'):
        sys.exit(f"mutate.sh: {listfile}:{lineno}: expected 'id|file|find|replace|why: ...'")
    cur[key] = val[1:] if val.startswith(' ') else val
if cur: entries.append(cur)
for e in entries:
    missing = [k for k in ('id', 'file', 'find', 'replace') if k not in e]
    if missing: sys.exit(f"mutate.sh: entry {e.get('id', '?')}: missing {', '.join(missing)}")
    for k in ('find', 'replace'): e[k] = e[k].replace('\\n', '\n')
ids = [e['id'] for e in entries]
if len(set(ids)) != len(ids): sys.exit("mutate.sh: duplicate mutation ids")
if cmd == 'ids':
    print('\n'.join(ids)); sys.exit(0)
if cmd == 'check':
    bad = []
    for e in entries:
        p = pathlib.Path(e['file'])
        n = p.read_text().count(e['find']) if p.is_file() else -1
        if n != 1:
            bad.append(f"  {e['id']}: {e['file']}: " + ("file not found" if n < 0 else f"snippet found {n} times (must be exactly once)")
                       + f"\n      snippet: {e['find']!r}")
    if bad: sys.exit("mutate.sh: the list no longer matches the code (re-target these entries):\n" + '\n'.join(bad))
    sys.exit(0)
e = next((x for x in entries if x['id'] == sys.argv[3]), None)
if e is None: sys.exit(f"mutate.sh: no mutation '{sys.argv[3]}'")
if cmd == 'field':
    print(e[sys.argv[4]] if sys.argv[4] in e else ''); sys.exit(0)
if cmd == 'apply':
    p = pathlib.Path(e['file']); text = p.read_text()
    if text.count(e['find']) != 1: sys.exit(f"mutate.sh: {e['id']}: snippet not found exactly once in {e['file']}")
    p.write_text(text.replace(e['find'], e['replace'], 1)); sys.exit(0)
sys.exit(f"mutate.sh: bad helper command {cmd}")
PY
}

helper check "$LIST" || exit 2
mapfile -t IDS < <(helper ids "$LIST")
if [[ -n "$ONLY" ]]; then
  IFS=',' read -r -a WANT <<<"$ONLY"
  for w in "${WANT[@]}"; do printf '%s\n' "${IDS[@]}" | grep -qx -- "$w" || { echo "mutate.sh: --only: no mutation '$w'" >&2; exit 2; }; done
  IDS=("${WANT[@]}")
fi

# ---- guaranteed restore ---------------------------------------------------------------------
MUTATED=""   # path of the file currently mutated ("" = none)
restore() {
  if [[ -n "$MUTATED" ]]; then
    cp "$WORK/original" "$MUTATED" && touch "$MUTATED"
    echo "mutate.sh: restored $MUTATED" >&2
    MUTATED=""
  fi
}
trap 'restore; rm -rf "$WORK"' EXIT
trap 'echo "mutate.sh: interrupted" >&2; exit 130' INT TERM

build() { cmake --build "$BUILD" -j "$JOBS" >"$1" 2>&1; }
run_tests() {  # $1 = log; returns ctest's status
  (cd "$BUILD" && timeout "$((TIMEOUT * 20))" ctest -j "$JOBS" --timeout "$TIMEOUT" "${REGEX[@]}" >"$1" 2>&1)
}
failed_tests() {  # names of the failed tests in a ctest log, comma-separated (at most 6)
  awk '/The following tests FAILED:/ {on = 1; next} on && /^[[:space:]]*[0-9]+ - / {
         sub(/^[[:space:]]*[0-9]+ - /, ""); sub(/ \([^)]*\)[[:space:]]*$/, ""); print }' "$1" |
    awk 'NR <= 6 {printf "%s%s", (NR > 1 ? ", " : ""), $0} END {if (NR > 6) printf " (+%d more)", NR - 6; if (NR == 0) printf "(ctest failed: see log)"}'
}

if [[ ! -f "$BUILD/CMakeCache.txt" ]]; then
  cmake -S "$ROOT" -B "$BUILD" -DCMAKE_BUILD_TYPE=Release >"$WORK/configure.log" 2>&1 ||
    { cat "$WORK/configure.log" >&2; exit 2; }
fi
if [[ "$BASELINE" == 1 ]]; then
  echo "mutate.sh: baseline build + ctest (unmutated)" >&2
  build "$WORK/build.log" || { tail -30 "$WORK/build.log" >&2; echo "mutate.sh: the unmutated tree does not build" >&2; exit 2; }
  run_tests "$WORK/ctest.log" || { echo "mutate.sh: the unmutated suite fails: $(failed_tests "$WORK/ctest.log")" >&2; exit 2; }
fi

ROWS=()
survived=0
errors=0
start=$(date +%s)
for id in "${IDS[@]}"; do
  file="$(helper field "$LIST" "$id" file)"
  t0=$(date +%s)
  echo "mutate.sh: [$id] $file" >&2
  cp "$file" "$WORK/original"
  MUTATED="$file"
  helper apply "$LIST" "$id"
  if ! build "$WORK/build-$id.log"; then
    result="BUILD ERROR"; tests="$(grep -m1 -E 'error' "$WORK/build-$id.log" | cut -c1-120)"; errors=$((errors + 1))
  elif run_tests "$WORK/ctest-$id.log"; then
    result="SURVIVED"; tests="—"; survived=$((survived + 1))
  else
    result="killed"; tests="$(failed_tests "$WORK/ctest-$id.log")"
  fi
  restore
  ROWS+=("| \`$id\` | $result | $tests | $(( $(date +%s) - t0 )) s |")
  echo "mutate.sh: [$id] $result ($tests)" >&2
done
echo "mutate.sh: rebuilding the unmutated tree" >&2
build "$WORK/build-final.log" || { tail -30 "$WORK/build-final.log" >&2; errors=$((errors + 1)); }

{
  echo "| mutation | result | failed tests | time |"
  echo "|---|---|---|---|"
  printf '%s\n' "${ROWS[@]}"
  echo
  echo "${#IDS[@]} mutations: $(( ${#IDS[@]} - survived - errors )) killed, $survived survived, $errors build errors ($(( $(date +%s) - start )) s)."
} | tee "${TABLE:-/dev/null}"
[[ $errors -gt 0 ]] && exit 2
[[ $survived -gt 0 ]] && exit 1
exit 0
