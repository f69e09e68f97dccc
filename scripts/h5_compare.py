#!/usr/bin/python3
"""Compare two HDF5 files dataset by dataset and attribute by attribute (bit-equal).

    h5_compare.py A.h5 B.h5 [--ignore REGEX]...

Exit status 0 when every dataset (shape, dtype, bytes) and every attribute of A equals B's
and both hold the same objects; 1 otherwise, listing the differences. Paths (datasets, or
"path@attribute" for attributes) matching an --ignore regex are skipped (e.g. timings).
Used by scripts/check-mpi.sh (files written across MPI ranks equal the
one-process files).
"""
import argparse
import re
import sys

import h5py
import numpy as np


def collect(f):
    items = {}

    def visit(name, obj):
        if isinstance(obj, h5py.Dataset):
            items["/" + name] = obj
        for k, v in obj.attrs.items():
            items["/" + name + "@" + k] = v

    for k, v in f.attrs.items():
        items["/@" + k] = v
    f.visititems(visit)
    return items


def equal(a, b):
    if isinstance(a, h5py.Dataset):
        if not isinstance(b, h5py.Dataset) or a.shape != b.shape or a.dtype != b.dtype:
            return False
        x, y = a[()], b[()]
        if isinstance(x, np.ndarray) and x.dtype.kind in "fciub":
            return x.tobytes() == y.tobytes()
        return np.array_equal(np.asarray(x), np.asarray(y))
    x, y = np.asarray(a), np.asarray(b)
    if x.shape != y.shape or x.dtype != y.dtype:
        return False
    if x.dtype.kind in "fciub":
        return x.tobytes() == y.tobytes()
    return np.array_equal(x, y)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("a")
    ap.add_argument("b")
    ap.add_argument("--ignore", action="append", default=[])
    args = ap.parse_args()
    ignore = [re.compile(r) for r in args.ignore]
    with h5py.File(args.a, "r") as fa, h5py.File(args.b, "r") as fb:
        ia, ib = collect(fa), collect(fb)
        diffs, compared = [], 0
        for k in sorted(set(ia) | set(ib)):
            if any(r.search(k) for r in ignore):
                continue
            if k not in ia or k not in ib:
                diffs.append(k + ": only in " + (args.a if k in ia else args.b))
            elif not equal(ia[k], ib[k]):
                diffs.append(k + ": differs")
            else:
                compared += 1
    for d in diffs:
        print("h5_compare: " + d)
    print("h5_compare: %s vs %s: %d objects equal, %d differ" % (args.a, args.b, compared, len(diffs)))
    return 1 if diffs else 0


if __name__ == "__main__":
    sys.exit(main())
