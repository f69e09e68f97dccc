#!/usr/bin/env python3
"""CHOLMOD simplicial against supernodal on the N-body hexagonal pile (benchmarks/micro/hex_pile.hpp):
one solve ("a step") of prox-newton and newton-sparse to R = 1e-6 (≤ 300 Newton iterations) from zero
and from 2000 nncg sweeps, and one numeric factorisation of each solver's matrix (newton-sparse's A_FF + ρI,
prox-newton's body-space H = M/Δt + Jᵀ D J). Both modes run alternated, ROUNDS times, through
build/bin/micro_newton with DC_CHOLMOD=simplicial|supernodal (docs/solvers.md "CHOLMOD: simplicial
or supernodal") and OPENBLAS_NUM_THREADS=1; medians of CPU time. Prints the CPU model and the load.

    scripts/cholmod-pile.py [--build build] [--bodies 10000] [--rounds 3] [--quick] [--json]

--quick: the factorisations only (seconds; the solves take minutes at 10,000 bodies). Not part of
`make test`.
"""
import argparse
import json
import os
import statistics
import subprocess
import sys

MODES = ("simplicial", "supernodal")
SOLVERS = {0: "newton-sparse", 1: "prox-newton"}
STARTS = {0: "zero", 1: "2000 nncg sweeps"}


def run(binary, mode, pattern):
    env = dict(os.environ, DC_CHOLMOD=mode, OPENBLAS_NUM_THREADS="1")
    out = subprocess.run([binary, f"--benchmark_filter={pattern}", "--benchmark_format=json"], env=env, check=True,
                         text=True, capture_output=True).stdout
    return [e for e in json.loads(out)["benchmarks"] if e.get("run_type") == "iteration"]


def machine():
    model = "?"
    try:
        for line in subprocess.run(["lscpu"], text=True, capture_output=True).stdout.splitlines():
            if line.startswith("Model name:"):
                model = line.split(":", 1)[1].strip()
    except OSError:
        pass
    return model, os.cpu_count(), open("/proc/loadavg").read().split()[:3]


def measure(build, bodies, rounds, quick):
    """{(what, mode): {"ms": [...], counters…}} over the rounds, modes alternated within each round."""
    binary = os.path.join(build, "bin", "micro_newton")
    pattern = f"BM_NewtonFactorize/{bodies}/0$|BM_BodyFactorize/{bodies}/0$"
    if not quick:
        pattern += f"|BM_PileSolve/bodies:{bodies}/"
    got = {}
    for r in range(rounds):
        for mode in (MODES if r % 2 == 0 else MODES[::-1]):
            for e in run(binary, mode, pattern):
                name = e["name"]
                if name.startswith("BM_PileSolve"):
                    a = dict(kv.split(":") for kv in name.split("/")[1:] if ":" in kv)
                    what = f"{SOLVERS[int(a['solver'])]} solve from {STARTS[int(a['start'])]}"
                else:
                    what = "newton-sparse factorisation (A_FF + ρI)" if "Newton" in name else \
                        "prox-newton factorisation (H = M/Δt + Jᵀ D J)"
                rec = got.setdefault((what, mode), {"ms": []})
                rec["ms"].append(e["cpu_time"])
                for k in ("factorizations", "newton", "passes", "residual_over_target", "contacts", "unknowns"):
                    if k in e:
                        rec[k] = e[k]
    return got


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--build", default="build")
    ap.add_argument("--bodies", type=int, default=10000, choices=(1000, 10000))
    ap.add_argument("--rounds", type=int, default=3)
    ap.add_argument("--quick", action="store_true", help="the factorisations only")
    ap.add_argument("--json", action="store_true", help="print the figures as JSON instead of a table")
    a = ap.parse_args()
    load_before = machine()[2]
    got = measure(a.build, a.bodies, a.rounds, a.quick)
    model, cores, load_after = machine()
    rows = []
    for what in dict.fromkeys(w for w, _ in got):
        s, p = got.get((what, "simplicial")), got.get((what, "supernodal"))
        if not s or not p:
            continue
        ms_s, ms_p = statistics.median(s["ms"]), statistics.median(p["ms"])
        rows.append({"what": what, "simplicial_ms": ms_s, "supernodal_ms": ms_p, "ratio": ms_p / ms_s,
                     "factorizations": s.get("factorizations"), "factorizations_supernodal": p.get("factorizations"),
                     "newton": s.get("newton"), "residual_over_target": s.get("residual_over_target"),
                     "residual_over_target_supernodal": p.get("residual_over_target"), "contacts": s.get("contacts")})
    stamp = {"cpu": model, "cores": cores, "load_before": load_before, "load_after": load_after, "bodies": a.bodies,
             "rounds": a.rounds, "quick": a.quick}
    if a.json:
        print(json.dumps({"stamp": stamp, "rows": rows}, indent=1))
        return 0
    print(f"# {a.bodies}-body hex pile, {rows[0]['contacts']:.0f} contacts; {model}, {cores} cores, load "
          f"{', '.join(load_before)} -> {', '.join(load_after)}; CPU ms, medians of {a.rounds} rounds")
    print("| what | simplicial ms | supernodal ms | supernodal / simplicial | factorisations (simpl. / supern.) | "
          "Newton it. | residual / target (simpl. / supern.) |")
    print("|---|---:|---:|---:|---:|---:|---:|")
    for r in rows:
        fac = "" if r["factorizations"] is None else f"{r['factorizations']:.0f} / {r['factorizations_supernodal']:.0f}"
        it = "" if r["newton"] is None else f"{r['newton']:.0f}"
        res = "" if r["residual_over_target"] is None else \
            f"{r['residual_over_target']:.2g} / {r['residual_over_target_supernodal']:.2g}"
        print(f"| {r['what']} | {r['simplicial_ms']:.1f} | {r['supernodal_ms']:.1f} | {r['ratio']:.2f} | {fac} | {it} | {res} |")
    return 0


if __name__ == "__main__":
    sys.exit(main())
