#!/usr/bin/python3
"""Copy a data set (docs/formats.md "Data set") without some of its feature channels.

    research/scripts/drop-feature-channels.py IN.h5 OUT.h5 coverage,orient_c,orient_s

Every other dataset and attribute is copied verbatim (same samples, labels, bodies, contacts
and split), /samples/features keeps the remaining channels in their order, and the root
attribute feature_channels lists them. So two models trained on IN and OUT differ only in the
input channels they see: the paired ablation of scripts/train-box-pile-model.sh.
"""
import os
import shutil
import sys

import h5py


def main(argv):
    if len(argv) != 4:
        sys.exit("usage: drop-feature-channels.py IN.h5 OUT.h5 CHANNEL[,CHANNEL...]")
    src, dst, drop = argv[1], argv[2], [c.strip() for c in argv[3].split(",") if c.strip()]
    with h5py.File(src, "r") as f:
        names = f.attrs["feature_channels"]
        names = (names.decode() if isinstance(names, bytes) else str(names)).split(",")
    missing = [c for c in drop if c not in names]
    if missing:
        sys.exit(f"drop-feature-channels.py: {src} has no feature channel(s) {','.join(missing)} "
                 f"(it has {','.join(names)})")
    keep = [i for i, c in enumerate(names) if c not in drop]
    if not keep:
        sys.exit("drop-feature-channels.py: nothing would be left")
    tmp = dst + ".partial"
    shutil.copyfile(src, tmp)
    with h5py.File(tmp, "r+") as f:
        old = f["/samples/features"]
        n, _, ny, nx = old.shape
        chunks = (min(4, max(n, 1)), len(keep), ny, nx)
        f.create_dataset("/samples/features_kept", shape=(n, len(keep), ny, nx), maxshape=(None, len(keep), ny, nx),
                         dtype=old.dtype, chunks=chunks, compression="gzip", compression_opts=4, shuffle=True)
        new = f["/samples/features_kept"]
        for a in range(0, n, 256):
            b = min(n, a + 256)
            new[a:b] = old[a:b][:, keep]
        del f["/samples/features"]
        f.move("/samples/features_kept", "/samples/features")
        f.attrs.modify("feature_channels", ",".join(names[i] for i in keep))
    # (The deleted dataset's space is not reclaimed: h5repack OUT.h5 shrinks the file.)
    os.replace(tmp, dst)
    print(f"{dst}: feature channels {','.join(names[i] for i in keep)} ({n} samples)")


if __name__ == "__main__":
    main(sys.argv)
