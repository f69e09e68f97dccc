#!/usr/bin/env python3
"""The stages of a step per contact row, from micro_step's BM_StepStages (thread CPU time).
With --settled: BM_StepStagesSettled (pgs-colored on the pile built at rest, creation order and
the default settings), its sweep_mb (the bytes one sweep streams) and BM_ReadRate, this core's
read rate over 1 to 256 MB: a sweep whose bytes lie where the rate has fallen to memory's
streams from memory.

Prints, per solver, body order (creation, morton numbering, or internal: `internal_order =
"morton"`, each step timed whole by World::step and split by its wall-clock profile) and size, the ns per contact row of each stage of World::step
(collide, assemble, warm start, solve, integrate) and, for pgs-colored, of the parts of its
solve (checks, colouring, ordering, packing, Δu⁰, sweeps, unpermute, residual), the total, its
ratio to the smallest size of the same solver and order, and the heap allocations per step
(medians over repetitions; 20 PGS sweeps; micro_step.cpp says how the pile is made).

  benchmarks/scripts/step-stages.py [MICRO_STEP] [--reps N] [--settled] [--json FILE]
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


def run(binary, reps, settled):
    with tempfile.NamedTemporaryFile(suffix=".json", delete=False) as f:
        out = f.name
    bench = "BM_StepStagesSettled|BM_ReadRate" if settled else "BM_StepStages/"
    subprocess.run([binary, f"--benchmark_filter={bench}", f"--benchmark_repetitions={reps}",
                    "--benchmark_format=json", f"--benchmark_out={out}"], check=True, stdout=subprocess.DEVNULL)
    with open(out) as f:
        data = json.load(f)
    os.unlink(out)
    return data


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("binary", nargs="?", default="build/bin/micro_step")
    ap.add_argument("--reps", type=int, default=3)
    ap.add_argument("--settled", action="store_true")
    ap.add_argument("--json")
    a = ap.parse_args()
    if a.json:
        with open(a.json) as f:
            data = json.load(f)
    else:
        data = run(a.binary, a.reps, a.settled)
    ctx = data.get("context", {})
    print(f"step-stages: host {ctx.get('host_name', '?')}, {ctx.get('num_cpus', '?')} CPUs, "
          f"load {ctx.get('load_avg', '?')}; ns per contact row (thread CPU time), medians")
    runs, rates = {}, {}
    for b in data["benchmarks"]:
        if b.get("run_type") != "iteration":
            continue
        name = b["run_name"] if "run_name" in b else b["name"]
        args = dict(kv.split(":") for kv in name.split("/")[1:] if ":" in kv)
        if name.startswith("BM_ReadRate"):
            rates.setdefault(int(args["MB"]), []).append(b["gb_per_s"])
            continue
        settled = name.startswith("BM_StepStagesSettled")
        key = (1 if settled else int(args["colored"]), int(args["morton"]), int(args["bodies"]))
        runs.setdefault(key, []).append(b)
    cols = STAGES + ["total"] + [f"s.{p}" for p in PARTS] + ["ratio", "allocs", "sweep_mb"]
    print(f"{'solver':12} {'order':8} {'bodies':>6} {'rows':>6} | " + " ".join(f"{c:>9}" for c in cols))
    first = {}
    for key in sorted(runs):
        colored, morton, n = key
        med = lambda k: statistics.median(b[k] for b in runs[key]) if k in runs[key][0] else float("nan")
        vals = [med(f"ns_{s}") for s in STAGES] + [med("ns_total")]
        vals += [med(f"ns_solve_{p}") for p in PARTS]
        first.setdefault((colored, morton), vals[5])
        vals += [vals[5] / first[(colored, morton)], med("allocs_step"), med("sweep_mb")]
        order = ("creation", "morton", "internal", "default")[morton]
        print(f"{'pgs-colored' if colored else 'pgs':12} {order:8} {n:6d} "
              f"{med('rows'):6.0f} | " + " ".join(f"{v:9.2f}" for v in vals))
    if rates:
        print("read rate (BM_ReadRate, GB/s, medians): " +
              ", ".join(f"{mb} MB {statistics.median(r):.0f}" for mb, r in sorted(rates.items())))


if __name__ == "__main__":
    sys.exit(main())
