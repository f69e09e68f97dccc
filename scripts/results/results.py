#!/usr/bin/env python3
"""`make results`: regenerates every figure the README and the docs quote.

    scripts/results/results.py [--build DIR] [--part bench,solvers,starters,cholmod,siconos,speed,build] [--full] [--keep]

Each part runs the project's programs (scripts/results/parts.py) and writes
docs/results/<part>.md; all parts together are docs/results/results.json. Every part is stamped
with the commit, the CPU model, the core count, the load average before and after, its wall
time and the exact commands (results.json also records the date). Then the blocks between `<!-- results:NAME -->` and
`<!-- /results -->` in README.md, DEVELOPERS.md and docs/*.md are rewritten from the JSON
(scripts/results/check_markers.py checks that they agree, in CI).

Parts run alone keep the other parts' records. Without --full the sizes are shortened so that
all parts take ~25 minutes on 2 cores (each part's note says how); --full runs the documented
defaults. Scratch output goes to build-results/ (removed with --keep absent, for the build part).
Not part of CI: timings depend on the machine and its load.
"""
import argparse
import json
import os
import platform
import shlex
import subprocess
import sys
import time

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import parts as parts_mod  # noqa: E402
import render  # noqa: E402


class Context:
    """What a part needs: the repository, the build directory, scratch space, and `run`, which
    records every command it runs for the stamp."""

    def __init__(self, root, build, full, keep):
        self.root, self.build, self.full, self.keep = root, build, full, keep
        self.tmp = os.path.join(root, "build-results")
        self.cores = os.cpu_count() or 1
        self.runs = []
        os.makedirs(self.tmp, exist_ok=True)

    def bin(self, name):
        return os.path.join(self.build, "bin", name)

    def pretty(self, cmd, env):
        rel = lambda w: os.path.relpath(w, self.root) if os.path.isabs(w) and w.startswith(self.root) else w
        words = [rel(w) for w in cmd]
        prefix = " ".join(f"{k}={rel(v)}" for k, v in (env or {}).items())
        return (prefix + " " if prefix else "") + shlex.join(words)

    def run(self, cmd, env=None, capture=True):
        self.runs.append(self.pretty(cmd, env))
        print(f"results: {self.runs[-1]}", flush=True)
        full_env = dict(os.environ, **(env or {}))
        r = subprocess.run(cmd, cwd=self.root, env=full_env, check=True, text=True,
                           stdout=subprocess.PIPE if capture else None)
        return r.stdout if capture else ""


def load_average():
    with open("/proc/loadavg") as fh:
        return ", ".join(fh.read().split()[:3])


def cpu_model():
    try:
        out = subprocess.run(["lscpu"], text=True, capture_output=True, check=True).stdout
        for line in out.splitlines():
            if line.startswith("Model name:"):
                return line.split(":", 1)[1].strip()
    except (OSError, subprocess.CalledProcessError):
        pass
    return platform.processor() or "unknown CPU"


def commit(root, build, binaries=True):
    """The tree's commit (with `-dirty` when tracked files differ) and the binaries' when they differ."""
    git = lambda *a: subprocess.run(["git", *a], cwd=root, text=True, capture_output=True).stdout.strip()
    head = git("rev-parse", "--short=12", "HEAD")
    dirty = "-dirty" if git("status", "--porcelain", "--untracked-files=no", "--", ".", ":!docs", ":!README.md") else ""
    try:
        version = subprocess.run([os.path.join(build, "bin", "deepcontact"), "--version"], text=True,
                                 capture_output=True).stdout
        binary = version.split("commit ")[1].split(")")[0] if "commit " in version else ""
    except OSError:
        binary = ""
    if binaries and binary and not head.startswith(binary) and not binary.startswith(head):
        return f"{head}{dirty} (binaries {binary})"
    return head + dirty


def run_part(ctx, name, argv):
    title, fn = parts_mod.PARTS[name]
    ctx.runs = []
    load_before, t0 = load_average(), time.time()
    blocks, notes = fn(ctx)
    stamp = {"commit": commit(ctx.root, ctx.build, binaries=name != "build"), "cpu": cpu_model(), "cores": ctx.cores,
             "load_before": load_before,
             "load_after": load_average(),
             "wall_seconds": round(time.time() - t0), "command": f"make results PART={name}" + (" FULL=1" if ctx.full else ""),
             "runs": ctx.runs}
    return {"part": name, "title": title, "stamp": stamp, "notes": notes, "blocks": blocks}


def write_all(root, data):
    os.makedirs(os.path.join(root, render.RESULTS_DIR), exist_ok=True)
    with open(os.path.join(root, render.JSON_PATH), "w") as fh:
        json.dump(data, fh, indent=1, ensure_ascii=False, sort_keys=True)
        fh.write("\n")
    for name, record in data["parts"].items():
        with open(os.path.join(root, render.RESULTS_DIR, name + ".md"), "w") as fh:
            fh.write(render.part_markdown(record))
    with open(os.path.join(root, render.RESULTS_DIR, "README.md"), "w") as fh:
        fh.write(render.index_markdown(data))
    for path in render.doc_files(root):
        text = open(path).read()
        new = render.fill_markers(text, data, os.path.relpath(path, root))
        if new != text:
            with open(path, "w") as fh:
                fh.write(new)
            print(f"results: filled markers in {os.path.relpath(path, root)}")


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[1])
    ap.add_argument("--build", default="build", help="build directory with bin/deepcontact and bin/micro_* (default build)")
    ap.add_argument("--part", default="", help="comma-separated parts (default all): " + ", ".join(parts_mod.PARTS))
    ap.add_argument("--full", action="store_true", help="the documented sizes instead of the shortened ones")
    ap.add_argument("--keep", action="store_true", help="keep the build part's fresh build directory")
    ap.add_argument("--fill-only", action="store_true", help="rewrite docs/results/*.md and the markers from the JSON")
    a = ap.parse_args()
    root = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
    names = [p for p in a.part.split(",") if p] or list(parts_mod.PARTS)
    unknown = [p for p in names if p not in parts_mod.PARTS]
    if unknown:
        print(f"results: unknown part '{unknown[0]}' (parts: {', '.join(parts_mod.PARTS)})", file=sys.stderr)
        return 2
    path = os.path.join(root, render.JSON_PATH)
    data = json.load(open(path)) if os.path.exists(path) else {"format": 1, "parts": {}}
    if not a.fill_only:
        ctx = Context(root, os.path.abspath(a.build), a.full, a.keep)
        for name in names:
            print(f"results: part {name}", flush=True)
            data["parts"][name] = run_part(ctx, name, sys.argv)
            write_all(root, data)  # after each part, so that an interrupted run keeps what it measured
    write_all(root, data)
    return 0


if __name__ == "__main__":
    sys.exit(main())
