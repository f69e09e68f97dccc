#!/usr/bin/env python3
"""Fail when a source folder holds more than --max source files (DEVELOPERS.md "Layout").

    scripts/check-folder-size.py --max 20

Counts the tracked C++ and Python sources (.cpp .hpp .h .py) of each folder, sub-folders
apart; a folder past the limit is split by subject (sub-folders), as the libraries' src/ are.
"""
import argparse
import collections
import subprocess
import sys


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--max", type=int, default=20, help="most source files per folder (default 20)")
    args = ap.parse_args()
    files = subprocess.run(["git", "ls-files", "*.cpp", "*.hpp", "*.h", "*.py"], check=True,
                           capture_output=True, text=True).stdout.split()
    count = collections.Counter(f.rsplit("/", 1)[0] if "/" in f else "." for f in files)
    over = sorted((n, d) for d, n in count.items() if n > args.max)
    for n, d in over:
        print(f"check-folder-size: {d}/ holds {n} source files (limit {args.max})")
    top = count.most_common(1)[0] if count else ("-", 0)
    print(f"check-folder-size: {len(count)} folders, the largest {top[0]}/ with {top[1]} files (limit {args.max})")
    return 1 if over else 0


if __name__ == "__main__":
    sys.exit(main())
