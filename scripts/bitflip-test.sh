#!/usr/bin/env bash
# Random single-bit flips in a model and in a data set — its manifest and a shard
# (docs/robustness.md "Checksums"):
# every flip must be detected (an error naming the damage) or harmless (it hit unused bytes:
# every value reads back unchanged) — 0 accepted silently. Two views:
#   1. every group, dataset and attribute read back through dc::H5File after each flip
#      (dc_io_tests H5Checksum.FlipsOfTheFileNamedByTheEnvironment; FLIPS per file);
#   2. as a user meets it: `deepcontact simulate --warmstart cnn:FLIPPED --hash` after each of
#      CLI_FLIPS flips of the model — exit 1, or the unflipped model's trajectory hash.
#   scripts/bitflip-test.sh            (BUILD=build FLIPS=100 CLI_FLIPS=20 SEED=1)
set -euo pipefail
BUILD=${BUILD:-build}
FLIPS=${FLIPS:-100}
CLI_FLIPS=${CLI_FLIPS:-20}
SEED=${SEED:-1}
DC="$BUILD/bin/deepcontact"
MODEL=${MODEL:-models/default.h5}
TMP=$(mktemp -d)
trap 'rm -rf "$TMP"' EXIT

"$DC" generate --sims 2 --steps 60 --seed 7 --threads 1 --out "$TMP/data.h5" >/dev/null
status=0
# A data set is a manifest (OUT) over one shard file per simulation (OUT.shards/RUN/sim-*.h5).
shard=$(ls "$TMP"/data.h5.shards/*/sim-000000.h5 2>/dev/null | head -1)
for f in "$MODEL" "$TMP/data.h5" $shard; do
  DC_BITFLIP_FILE="$f" DC_BITFLIP_COUNT="$FLIPS" DC_BITFLIP_SEED="$SEED" \
    "$BUILD/tests/dc_io_tests" --gtest_filter=H5Checksum.FlipsOfTheFileNamedByTheEnvironment --gtest_brief=1 \
    | grep -E '^(bitflip|  )' || status=1
done

scene=(--steps 60 --set bodies.count=30)
want=$("$DC" simulate "${scene[@]}" --warmstart "cnn:$MODEL" --hash)
detected=0 harmless=0 silent=0
for ((i = 0; i < CLI_FLIPS; i++)); do
  /usr/bin/python3 - "$MODEL" "$TMP/flipped.h5" "$((SEED * 1000 + i))" <<'PY'
import random, sys
data = bytearray(open(sys.argv[1], "rb").read())
bit = random.Random(int(sys.argv[3])).randrange(8 * len(data))
data[bit // 8] ^= 1 << (bit % 8)
open(sys.argv[2], "wb").write(data)
PY
  if got=$("$DC" simulate "${scene[@]}" --warmstart "cnn:$TMP/flipped.h5" --hash 2>"$TMP/err"); then
    if [ "$got" = "$want" ]; then harmless=$((harmless + 1)); else silent=$((silent + 1)); fi
  else
    detected=$((detected + 1))
    [ "$detected" = 1 ] && echo "  first error: $(cat "$TMP/err")"
  fi
done
echo "simulate with a flipped $MODEL: $CLI_FLIPS flips: $detected refused, $harmless same trajectory, $silent changed the trajectory silently"
[ "$silent" = 0 ] || status=1
exit $status
