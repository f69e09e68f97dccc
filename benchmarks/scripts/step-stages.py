#!/usr/bin/env python3
"""The stages of a step per contact row, from micro_step's BM_StepStages (thread CPU time).

Prints, per solver, body order (creation, morton numbering, or internal: `internal_order =
"morton"`, each step timed whole by World::step and split by its wall-clock profile) and size, the ns per contact row of each stage of World::step
(collide, assemble, warm start, solve, integrate) and, for pgs-colored, of the parts of its
solve (checks, colouring, ordering, packing, Δu⁰, sweeps, unpermute, residual), the total, its
ratio to the smallest size of the same solver and order, and the heap allocations per step
(medians over repetitions; 20 PGS sweeps; micro_step.cpp says how the pile is made).

  benchmarks/scripts/step-stages.py [MICRO_STEP] [--reps N] [--json FILE]
    MICRO_STEP  default build/bin/micro_step
    --json      read an earlier run's --benchmark_out JSON instead of running
"""
import argparse
import json
import os
import statistics
import subprocess
import sys
import tempfile

STAGES = ["collide", "assemble", "warm", "solve", "integrate"]
PARTS = ["checks", "coloring", "ordering", "pack", "du0", "sweeps", "unpermute", "residual"]


def run(binary, reps):
    with tempfile.NamedTemporaryFile(suffix=".json", delete=False) as f:
        out = f.name
    subprocess.run([binary, "--benchmark_filter=BM_StepStages", f"--benchmark_repetitions={reps}",
                    "--benchmark_format=json", f"--benchmark_out={out}"], check=True, stdout=subprocess.DEVNULL)
    with open(out) as f:
        data = json.load(f)
    os.unlink(out)
    return data


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("binary", nargs="?", default="build/bin/micro_step")
    ap.add_argument("--reps", type=int, default=3)
    ap.add_argument("--json")
    a = ap.parse_args()
    if a.json:
        with open(a.json) as f:
            data = json.load(f)
    else:
        data = run(a.binary, a.reps)
    ctx = data.get("context", {})
    print(f"step-stages: host {ctx.get('host_name', '?')}, {ctx.get('num_cpus', '?')} CPUs, "
          f"load {ctx.get('load_avg', '?')}; ns per contact row (thread CPU time), medians")
    runs = {}
    for b in data["benchmarks"]:
        if b.get("run_type") != "iteration":
            continue
        name = b["run_name"] if "run_name" in b else b["name"]
        args = dict(kv.split(":") for kv in name.split("/")[1:] if ":" in kv)
        key = (int(args["colored"]), int(args["morton"]), int(args["bodies"]))
        runs.setdefault(key, []).append(b)
    cols = STAGES + ["total"] + [f"s.{p}" for p in PARTS] + ["ratio", "allocs"]
    print(f"{'solver':12} {'order':8} {'bodies':>6} {'rows':>6} | " + " ".join(f"{c:>9}" for c in cols))
    first = {}
    for key in sorted(runs):
        colored, morton, n = key
        med = lambda k: statistics.median(b[k] for b in runs[key]) if k in runs[key][0] else float("nan")
        vals = [med(f"ns_{s}") for s in STAGES] + [med("ns_total")]
        vals += [med(f"ns_solve_{p}") for p in PARTS]
        first.setdefault((colored, morton), vals[5])
        vals += [vals[5] / first[(colored, morton)], med("allocs_step")]
        order = ("creation", "morton", "internal")[morton]
        print(f"{'pgs-colored' if colored else 'pgs':12} {order:8} {n:6d} "
              f"{med('rows'):6.0f} | " + " ".join(f"{v:9.2f}" for v in vals))


if __name__ == "__main__":
    sys.exit(main())
