#!/usr/bin/env python3
"""Where a step's cost per contact row grows with the body count: perf samples (cpu-clock) of one
micro_step whole-step benchmark at several sizes, per function in ns per contact row and step.

  benchmarks/scripts/step-row-profile.py [--bin build/bin/micro_step]
      [--bench BM_ColoredStepOnlySettled] [--order 3] [--sizes 1000 40000] [--top 25]

For each size the script first runs the benchmark briefly to time the pile's construction (the
piles are built inside the benchmark, by the same functions a step runs), then records with
`perf record -D` from past that time, so the samples are those of the timed steps (and of the
untimed copy of the world before each step: memmove and the operator= rows). ns/row = samples /
frequency / iterations / rows. Rows are sorted by their growth from the first size to the last.
Needs perf (cpu-clock events work in VMs without hardware counters). Figures are CPU time of the
process: on a loaded machine run it more than once.
"""
import argparse
import json
import os
import re
import subprocess
import sys
import tempfile
import time


def run_bench(binary, bench_filter, min_time, json_out, perf_out=None, delay_ms=0, freq=2000):
    cmd = [binary, f"--benchmark_filter={bench_filter}", f"--benchmark_min_time={min_time}",
           "--benchmark_format=json", f"--benchmark_out={json_out}"]
    if perf_out:
        cmd = ["perf", "record", "-q", "-e", "cpu-clock", "-F", str(freq), "-D", str(delay_ms), "-o", perf_out,
               "--"] + cmd
    t0 = time.monotonic()
    subprocess.run(cmd, check=True, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    return time.monotonic() - t0


def samples_by_symbol(perf_data):
    out = subprocess.run(["perf", "report", "-i", perf_data, "--stdio", "-n", "--sort", "sym"],
                         capture_output=True, text=True, check=True).stdout
    counts = {}
    for line in out.splitlines():
        m = re.match(r"\s+[\d.]+%\s+(\d+)\s+\[.\]\s+(.*)", line)
        if m:
            name = m.group(2).strip()
            counts[name] = counts.get(name, 0) + int(m.group(1))
    return counts


def profile(binary, bench, order, n, min_time, freq, tmp):
    bench_filter = f"^{bench}/bodies:{n}/sweeps:20/morton:{order}$"
    build_s = run_bench(binary, bench_filter, 0.01, os.path.join(tmp, "probe.json"))
    perf_data, json_out = os.path.join(tmp, f"perf_{n}.data"), os.path.join(tmp, f"bench_{n}.json")
    run_bench(binary, bench_filter, min_time, json_out, perf_data, int(1000 * build_s) + 1000, freq)
    with open(json_out) as f:
        b = json.load(f)["benchmarks"][0]
    per_sample = 1e9 / freq / b["iterations"] / b["rows"]
    return b, {k: v * per_sample for k, v in samples_by_symbol(perf_data).items()}


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--bin", default="build/bin/micro_step")
    ap.add_argument("--bench", default="BM_ColoredStepOnlySettled")
    ap.add_argument("--order", type=int, default=3, help="micro_step's morton argument (3: default settings)")
    ap.add_argument("--sizes", type=int, nargs="+", default=[1000, 40000])
    ap.add_argument("--min-time", type=float, default=5.0, help="benchmark_min_time of the recorded run [s]")
    ap.add_argument("--freq", type=int, default=2000, help="perf sampling frequency [Hz]")
    ap.add_argument("--top", type=int, default=25)
    args = ap.parse_args()
    with tempfile.TemporaryDirectory() as tmp:
        runs = [profile(args.bin, args.bench, args.order, n, args.min_time, args.freq, tmp) for n in args.sizes]
    for n, (b, _) in zip(args.sizes, runs):
        print(f"{args.bench} bodies {n}: {b['us_per_row'] * 1e3:.1f} ns/row (benchmark), rows {b['rows']:.0f}, "
              f"iterations {b['iterations']}")
    print(f"load {os.getloadavg()}; ns per contact row and step (perf cpu-clock samples), sorted by growth")
    names = set().union(*(r.keys() for _, r in runs))
    first, last = runs[0][1], runs[-1][1]
    rows = sorted(names, key=lambda k: last.get(k, 0.0) - first.get(k, 0.0), reverse=True)[: args.top]
    print("  ".join(f"{n:>9d}" for n in args.sizes) + "     growth  function")
    for k in rows:
        vals = [r.get(k, 0.0) for _, r in runs]
        print("  ".join(f"{v:9.2f}" for v in vals) + f"  {vals[-1] - vals[0]:+9.2f}  {k[:100]}")
    total = [sum(r.values()) for _, r in runs]
    print("  ".join(f"{v:9.2f}" for v in total) + f"  {total[-1] - total[0]:+9.2f}  (all samples)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
