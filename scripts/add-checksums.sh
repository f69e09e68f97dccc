#!/usr/bin/env bash
# Re-writes HDF5 files through DeepContact's HDF5 layer so that they carry its checksums
# (docs/formats.md "Checksums"): every value bit-equal, each file replaced atomically.
#   scripts/add-checksums.sh models/*.h5        (BUILD=build by default)
set -euo pipefail
BUILD=${BUILD:-build}
[ $# -ge 1 ] || { echo "usage: $0 FILE.h5..." >&2; exit 2; }
for f in "$@"; do
  PYTHONPATH="$BUILD/python" /usr/bin/python3 -c 'import sys, deepcontact; deepcontact.copy_hdf5(sys.argv[1], sys.argv[2])' \
    "$f" "$f.with-checksums"
  mv "$f.with-checksums" "$f"
  echo "$f: re-written with checksums"
done
