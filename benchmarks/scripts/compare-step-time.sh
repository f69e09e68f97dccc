#!/usr/bin/env bash
# Seed-scene step time of two deepcontact builds, side by side in one run (the shape
# machinery must not slow circle scenes). Alternates the two binaries R times and prints each
# run's user CPU time and the median ratio, so machine load hits both alike.
#
#   benchmarks/scripts/compare-step-time.sh BEFORE_BINARY AFTER_BINARY [ROUNDS=5] [STEPS=200]
#
# e.g. before = a build of the merge base, after = build/bin/deepcontact. Each run is
# `simulate --scene scenes/seed.toml --set time.steps=STEPS --hash` (the hashes must agree).
set -euo pipefail
before="$1"; after="$2"; rounds="${3:-5}"; steps="${4:-200}"
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
run() {  # prints "user_seconds hash"
  local out t
  out=$( { /usr/bin/time -f "%U" "$1" simulate --scene "$root/scenes/seed.toml" --set "time.steps=$steps" --hash; } 2>&1 )
  t=$(printf '%s\n' "$out" | tail -1)
  printf '%s %s\n' "$t" "$(printf '%s\n' "$out" | grep -E '^[0-9a-f]{16}$' | head -1)"
}
tb=(); ta=()
for ((r = 1; r <= rounds; r++)); do
  read -r b hb < <(run "$before")
  read -r a ha < <(run "$after")
  [[ "$hb" == "$ha" ]] || { echo "hash differs: $hb vs $ha" >&2; exit 1; }
  echo "round $r: before ${b}s after ${a}s (hash $ha)"
  tb+=("$b"); ta+=("$a")
done
/usr/bin/python3 - "${tb[@]}" -- "${ta[@]}" <<'PY'
import sys, statistics
args = sys.argv[1:]; i = args.index("--")
b = [float(x) for x in args[:i]]; a = [float(x) for x in args[i + 1:]]
print(f"median user CPU: before {statistics.median(b):.3f} s, after {statistics.median(a):.3f} s, "
      f"after/before {statistics.median(a) / statistics.median(b):.4f}")
PY
