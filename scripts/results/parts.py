"""The parts of `make results`: each runs the project's own programs and returns its blocks
(scripts/results/render.py describes a block). Sizes are chosen so that a whole run stays
within ~25 minutes on 2 cores; each part says what it shortened in its notes.
"""
import csv
import glob
import importlib.util
import json
import os
import re
import shutil
import statistics
import subprocess
import time


def mb(path):
    """Size in MB (10^6 bytes) of a file or a directory tree."""
    if os.path.isfile(path):
        return os.path.getsize(path) / 1e6
    total = 0
    for d, _, files in os.walk(path):
        total += sum(os.path.getsize(os.path.join(d, f)) for f in files if not os.path.islink(os.path.join(d, f)))
    return total / 1e6


def gbench(ctx, binary, pattern, extra=()):
    """Runs a Google Benchmark binary with a filter; its JSON "benchmarks" entries."""
    out = ctx.run([ctx.bin(binary), f"--benchmark_filter={pattern}", "--benchmark_format=json", *extra])
    return json.loads(out)["benchmarks"]


def ci(x, spec):
    return f"{x['estimate']:{spec}} [{x['lo']:{spec}}, {x['hi']:{spec}}]"


def part_bench(ctx):
    """The default bench (every default starter, the seed scene), on fewer seeds."""
    seeds = "1..8" if ctx.full else "1..4"
    out = os.path.join(ctx.tmp, "bench")
    shutil.rmtree(out, ignore_errors=True)
    t0 = time.time()
    ctx.run([ctx.bin("deepcontact"), "bench", "--seeds", seeds, "--jobs", str(ctx.cores), "--out", out], capture=False)
    wall = time.time() - t0
    s = json.load(open(os.path.join(out, "summary.json")))
    st = s["statistics"]["warmstarters"]
    rows = []
    for name, w in s["warmstarters"].items():
        oracle = " *" if w["uses_oracle"] else ""
        rows.append([f"`{name}`{oracle}", ci(st[name]["median_sweeps_to_tol"], ".0f"), f"{100 * w['unconverged_share']:.1f} %",
                     f"{w['warmstart_ms']:.4f}", f"{w['solve_ms']:.3f}", ci(st[name]["median_total_ms"], ".3f"),
                     f"{w['total_ratio_to_zero']:.3f}"])
    table = {"name": "bench-default", "title": "Default bench: warm starters on the seed scene",
             "note": (f"`deepcontact bench --seeds {seeds}`: solver `{s['solver']}`, {s['sweeps']} sweeps, θ ≤ "
                      f"{s['tolerance']} N, {s['evaluated_steps']} evaluated steps, medians over steps with bootstrap 95 % "
                      "intervals; `*` = oracle starter (reads this step's solution; its cost is not in total)."
                      + ("" if ctx.full else " Seeds 1..4 instead of the default 1..8 (time budget): intervals are wider.")),
             "columns": ["warm starter", "sweeps to tol (median)", "never", "warm start ms", "solve ms", "total ms (median)",
                         "total / zero"], "rows": rows}
    files = sorted(os.listdir(out))
    run = {"name": "bench-run", "title": "What the bench run writes",
           "note": "Wall time of the run above and the size of its output directory.",
           "columns": ["command", "wall s", "results.h5 MB", "directory MB", "files"],
           "rows": [[f"`deepcontact bench --seeds {seeds} --jobs {ctx.cores}`", f"{wall:.0f}",
                     f"{mb(os.path.join(out, 'results.h5')):.1f}", f"{mb(out):.1f}", str(len(files))]]}
    return [table, run], []


def load_table_module(ctx):
    path = os.path.join(ctx.root, "research", "scripts", "solver-comparison-table.py")
    spec = importlib.util.spec_from_file_location("solver_comparison_table", path)
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


def part_solvers(ctx):
    """Solver × warm start per scene family (research/scripts/solver-comparison.sh), STEPS per seed."""
    steps = "10" if ctx.full else "6"
    out = os.path.join(ctx.tmp, "solvers")
    shutil.rmtree(out, ignore_errors=True)
    ctx.run([os.path.join("research", "scripts", "solver-comparison.sh"), ctx.build, out],
            env={"NO_DOCS": "1", "STEPS": steps}, capture=False)
    markdown, notes = load_table_module(ctx).table(out)
    lines = [ln for ln in markdown.splitlines()[2:] if ln.startswith("|")]
    rows = [[c.strip() for c in ln.strip("|").split("|")] for ln in lines]
    cols = ["family", "solver + start", "reached R", "ms to R", "iterations to R", "total ms", "ms to R / pgs+builtin total",
            "total / pgs+builtin total"]
    block = {"name": "solver-warmstart", "title": "Solver × warm start per scene family",
             "note": (f"Paired bench with `--solvers pgs,nncg,newton-sparse --accuracy 1e-6`: reached R = share of steps whose "
                      "natural-map residual reaches 1e-6 · max_i m_i |g| within 10,000 iterations; total = warm start + solve "
                      "to θ ≤ 1e-2 N; medians with bootstrap 95 % intervals. "
                      f"{steps} evaluated steps per seed" + ("" if ctx.full else " (STEPS=6 instead of 10: time budget)")
                      + ". Runs: " + "; ".join(notes) + "."),
             "columns": cols, "rows": rows}
    return [block], []


# The families of the solver × starter table: (family, scene, cnn model, first evaluated step,
# evaluated steps shortened / full; an odd shortened count where more than one step, so that a
# median is one step's figure, not the mean of an easy and a hard step). Seeds 5 (shortened) or
# 5, 6 (full; deep: 5): held out from tuning. impact_1000 uses the impact model (the same family at 1,000 bodies).
STARTER_FAMILIES = [("impact", "impact", "impact", 195, 5, 8), ("impact_1000", "impact_1000", "impact", 221, 1, 6),
                    ("deep settled", "deep", "deep", 480, 1, 6), ("pour", "pour", "pour", 200, 3, 6),
                    ("polydisperse", "polydisperse", "polydisperse", 185, 3, 6),
                    ("box_pile", "box_pile", "box_pile", 250, 3, 6)]
STARTER_SOLVERS = "prox-newton,newton-sparse,nncg,pgs"


def solver_pairs_h5(path):
    """{(solver, starter): {figure: (estimate, lo, hi)}, "p99_factorizations", "p99_factorizations_to_accuracy",
    "steps"} of a bench's results.h5."""
    import h5py
    import numpy as np
    text = lambda v: v.decode() if isinstance(v, bytes) else str(v)
    pairs = {}
    with h5py.File(path, "r") as f:
        s = f["solvers"]
        figures = [text(x) for x in s["interval_figures"][()]]
        iv = s["intervals"][()]
        for i, g in enumerate(text(x) for x in s["pair_groups"][()]):
            key = (text(s[g].attrs["solver"]), text(s[g].attrs["starter"]))
            pairs[key] = {fig: tuple(float(v) for v in iv[i, j]) for j, fig in enumerate(figures)}
            fac = s[g]["factorizations"][()]
            pairs[key]["p99_factorizations"] = float(np.percentile(fac, 99)) if len(fac) and fac.min() >= 0 else None
            fac_r = s[g]["factorizations_to_accuracy"][()] if "factorizations_to_accuracy" in s[g] else np.array([])
            pairs[key]["p99_factorizations_to_accuracy"] = \
                float(np.percentile(fac_r, 99)) if len(fac_r) and fac_r.min() >= 0 else None
            pairs[key]["steps"] = len(s[g]["seed"])
    return pairs


def part_starters(ctx):
    """Warm start × solver, prox-newton included: `deepcontact bench --solvers … --accuracy 1e-6` per family."""
    rows, runs = [], []
    os.makedirs(os.path.join(ctx.tmp, "starters"), exist_ok=True)
    for family, scene, model, first, short, full in STARTER_FAMILIES:
        steps = full if ctx.full else short
        seeds = ("5" if scene == "deep" else "5,6") if ctx.full else "5"
        out = os.path.join(ctx.tmp, "starters", scene)
        shutil.rmtree(out, ignore_errors=True)
        starters = f"zero,builtin,builtin-extrapolate,cnn:models/{model}.h5,copy"
        t0 = time.time()
        ctx.run([ctx.bin("deepcontact"), "bench", "--solvers", STARTER_SOLVERS, "--accuracy", "1e-6", "--sweeps", "1000",
                 "--max-sweeps", "10000", "--scene", f"scenes/{scene}.toml", "--warmstarts", starters, "--seeds", seeds,
                 "--jobs", str(min(ctx.cores, len(seeds.split(",")))), "--warmup-steps", str(first),
                 "--steps", str(first + steps), "--out", out], capture=False)
        runs.append(f"{family} steps {first}–{first + steps - 1}, seeds {seeds}, {time.time() - t0:.0f} s")
        pairs = solver_pairs_h5(os.path.join(out, "results.h5"))
        for (solver, starter), x in pairs.items():
            def fac_text(median, p99):
                m = x.get(median)
                if m is None or m[0] != m[0] or x.get(p99) is None:
                    return "–"
                return f"{ci(dict(zip(('estimate', 'lo', 'hi'), m)), '.0f')} ({x[p99]:.0f})"
            fac = fac_text("median_factorizations_to_accuracy", "p99_factorizations_to_accuracy")
            fac_whole = fac_text("median_factorizations", "p99_factorizations")
            iv = lambda k, spec: ci(dict(zip(("estimate", "lo", "hi"), x[k])), spec) if x[k][0] == x[k][0] else "–"
            rows.append([family, solver, "cnn" if starter.startswith("cnn:") else starter, iv("reached_share", ".2f"),
                         iv("median_iterations_to_accuracy", ".0f"), fac, fac_whole, iv("median_ms_to_accuracy", ".3g"),
                         iv("ms_to_accuracy_over_pgs_builtin_total", ".3g")])
    block = {"name": "solver-starter", "title": "Warm start × solver to R = 1e-6, prox-newton included",
             "note": ("Per family `deepcontact bench --solvers " + STARTER_SOLVERS + " --accuracy 1e-6 --sweeps 1000 "
                      "--max-sweeps 10000 --warmstarts zero,builtin,builtin-extrapolate,cnn:models/MODEL.h5,copy` (paired: "
                      "every pair solves the identical LCPs; cnn = the family's shipped model, impact's for impact_1000; "
                      "copy = this step's oracle λ*). reached = share of steps at R within 10,000 iterations; iterations "
                      "to R = Newton iterations (prox-newton, newton-sparse) or sweeps (nncg, pgs), never-reached steps at "
                      "the cap; factorisations to R = numeric factorisations (prox-newton, newton-sparse) up to the first "
                      "checkpoint at R, where ms to R is taken (the whole run for a step that never gets there), median "
                      "(p99); whole solve = the same over the traced solve down to R/100 (the solver's own stop), median "
                      "(p99); "
                      "ms to R includes the warm start; medians with bootstrap 95 % intervals; wall-clock ms, the pairs "
                      "interleaved step by step. " + ("" if ctx.full else "Shortened (time budget): seed 5 only, 1–5 "
                      "evaluated steps per family, so the intervals are those of these few steps; `FULL=1`: seeds 5, 6 "
                      "and 6–8 steps. ") + "Runs: " + "; ".join(runs) + "."),
             "columns": ["family", "solver", "starter", "reached R", "iterations to R", "factorisations to R (p99)",
                         "factorisations, whole solve (p99)", "ms to R",
                         "ms to R / pgs+builtin total"], "rows": rows}
    return [block], []


def part_cholmod(ctx):
    """CHOLMOD simplicial against supernodal on the 10,000-body pile (scripts/cholmod-pile.py)."""
    args = ["--bodies", "10000", "--rounds", "1" if ctx.full else "3"] + ([] if ctx.full else ["--quick"])
    got = json.loads(ctx.run(["/usr/bin/python3", os.path.join("scripts", "cholmod-pile.py"), "--build", ctx.build,
                              "--json", *args]))
    rows, contacts = [], got["rows"][0]["contacts"] if got["rows"] else 0
    for r in got["rows"]:
        fac = "–" if r["factorizations"] is None else f"{r['factorizations']:.0f} / {r['factorizations_supernodal']:.0f}"
        res = "–" if r["residual_over_target"] is None else \
            f"{r['residual_over_target']:.2g} / {r['residual_over_target_supernodal']:.2g}"
        rows.append([r["what"], f"{r['simplicial_ms']:.1f}", f"{r['supernodal_ms']:.1f}", f"{r['ratio']:.2f}", fac, res])
    block = {"name": "cholmod-10k", "title": "CHOLMOD simplicial against supernodal, 10,000-body pile",
             "note": (f"`scripts/cholmod-pile.py {' '.join(args)}`: micro_newton on the hexagonal pile of micro_pgs "
                      f"(10,000 bodies, {contacts:.0f} contacts), DC_CHOLMOD=simplicial "
                      "and =supernodal alternated, OPENBLAS_NUM_THREADS=1, CPU ms (medians over the rounds): one numeric "
                      "factorisation of each solver's matrix" + (", and one solve (≤ 300 Newton iterations) to R = 1e-6 of the "
                      "weight from zero and from 2000 nncg sweeps." if ctx.full else ". Shortened (time budget): the "
                      "factorisations only (`FULL=1`: one round with the solves, which take minutes).")),
             "columns": ["what", "simplicial ms", "supernodal ms", "supernodal / simplicial",
                         "factorisations (simpl. / supern.)", "residual / target (simpl. / supern.)"], "rows": rows}
    return [block], []


def part_siconos(ctx):
    """Siconos numerics' NSGS and ours on the same frictional problems (benchmarks/scripts/siconos-figures.sh)."""
    if not os.path.exists(ctx.bin("siconos_compare")):
        return [{"name": "siconos", "title": "Side by side with Siconos", "columns": [], "rows": [], "note": "",
                 "skipped": "siconos_compare not built (scripts/install-deps.sh --siconos)"}], []
    out = os.path.join(ctx.tmp, "siconos")
    shutil.rmtree(out, ignore_errors=True)
    ctx.run([os.path.join("benchmarks", "scripts", "siconos-figures.sh"), ctx.build, out], env={"REPEAT": "1"}, capture=False)
    rows = []
    with open(os.path.join(out, "compare.csv")) as fh:
        for r in csv.DictReader(fh):
            rows.append([f"`{os.path.basename(r['file'])}`", r["contacts"], r["side"], r["solver"], r["status"], r["iterations"],
                         f"{float(r['cpu_seconds']):.4g}", f"{float(r['residual']):.2e}"])
    block = {"name": "siconos", "title": "Side by side with Siconos",
             "note": ("`siconos_compare` on Siconos' 2D test files of ≥ 300 contacts and on problems exported by the engine "
                      "(impact steps 105, 210; deep steps 250, 500): CPU seconds of one solve (REPEAT=1), NSGS capped at "
                      "20,000 iterations, residual in each side's own measure (docs/lcp.md)."),
             "columns": ["problem", "contacts", "side", "solver", "status", "iterations", "CPU s", "residual"], "rows": rows}
    return [block], []


def lcp_solve(ctx, path, args):
    """`deepcontact lcp solve FILE ARGS…`: its JSON (z, w, mu dropped), or the error line."""
    cmd = [ctx.bin("deepcontact"), "lcp", "solve", path, *args]
    ctx.runs.append(ctx.pretty(cmd, None))
    r = subprocess.run(cmd, cwd=ctx.root, text=True, capture_output=True)
    try:
        return json.loads(r.stdout)
    except json.JSONDecodeError:
        lines = [ln for ln in r.stderr.splitlines() if "error" in ln]
        return {"status": "error", "message": (lines or ["exit %d" % r.returncode])[-1]}


def part_lcp(ctx):
    """`lcp solve` on every Siconos 2D test file: the default route, `newton`, the proximal route."""
    files = sorted(glob.glob(os.path.join(ctx.root, "tests", "data", "fc2d", "*.dat")))
    routes = [("no options", []), ("`--solver newton`", ["--solver", "newton"]),
              ("`--solver newton-sparse --proximal`", ["--solver", "newton-sparse", "--proximal"])]
    rows = []
    for f in files:
        with open(f) as fh:
            contacts = fh.read(200).split()[1]
        row = [f"`{os.path.basename(f)}`", contacts]
        for _, args in routes:
            j = lcp_solve(ctx, f, args)
            if j.get("status") in ("error", "invalid_input"):
                row.append(f"{j['status']}: {j.get('message', '').split(' (')[0][:70]}")
                continue
            it = j.get("sweeps", j.get("iterations", "?"))
            row.append(f"{j.get('solver', '?')}: {j['status']}, {it} it., residual {j['residual']:.1e}, "
                       f"{j['solve_seconds']:.3g} s")
        rows.append(row)
    block = {"name": "lcp-siconos-files", "title": "`lcp solve` on Siconos' 2D test problems",
             "note": ("Every file of tests/data/fc2d/ (Siconos numerics' 2D FrictionContactProblem test data): solver, "
                      "status, iterations, the natural-map residual (absolute) and the CPU seconds of the solve, from the "
                      "JSON of `deepcontact lcp solve FILE`."),
             "columns": ["file", "contacts"] + [r[0] for r in routes], "rows": rows}
    return [block], []


def median_by(entries, key, field):
    groups = {}
    for e in entries:
        if e.get("run_type") == "iteration":
            groups.setdefault(key(e["name"]), []).append(e[field])
    return {k: statistics.median(v) for k, v in groups.items()}


def block_kernels(ctx):
    pgs = gbench(ctx, "micro_pgs", "BM_SeedScenePgs(Colored|Baseline)?$|BM_(PgsColored|PgsBaseline)/bodies:(1000|10000)/"
                 "sweeps:200/order:0(/kernel:2)?$", ["--benchmark_min_time=0.2"])
    ns = {e["name"]: e["ns_per_row_sweep"] for e in pgs if "ns_per_row_sweep" in e}
    rows = []
    for label, ours, ref in [("seed pile (micro_pgs BM_SeedScene*)", "BM_SeedScenePgsColored", "BM_SeedScenePgsBaseline"),
                             ("1,000-body pile", "BM_PgsColored/bodies:1000/sweeps:200/order:0/kernel:2",
                              "BM_PgsBaseline/bodies:1000/sweeps:200/order:0"),
                             ("10,000-body pile", "BM_PgsColored/bodies:10000/sweeps:200/order:0/kernel:2",
                              "BM_PgsBaseline/bodies:10000/sweeps:200/order:0")]:
        if ours in ns and ref in ns:
            rows.append([f"`pgs-colored` AVX-512 vs the scalar loop, {label}", f"{ns[ours]:.2f} vs {ns[ref]:.2f} ns per row·sweep",
                         f"{ns[ours] / ns[ref]:.2f}×"])
    if "BM_SeedScenePgs" in ns and "BM_SeedScenePgsBaseline" in ns:
        rows.append(["`pgs` vs the scalar loop, seed pile", f"{ns['BM_SeedScenePgs']:.2f} vs "
                     f"{ns['BM_SeedScenePgsBaseline']:.2f} ns per row·sweep", f"{ns['BM_SeedScenePgs'] / ns['BM_SeedScenePgsBaseline']:.2f}×"])
    return {"name": "speed-kernels", "title": "PGS kernels (Google Benchmark, CPU time)",
            "note": "`micro_pgs` with `--benchmark_min_time=0.2`, one thread; the scalar loop is `BM_PgsBaseline`.",
            "columns": ["what", "measured", "ratio"], "rows": rows}


def block_cnn(ctx):
    cnn = gbench(ctx, "micro_cnn", "^cnn_warm_start/default", ["--benchmark_min_time=0.2"])
    rows = []
    for e in cnn:
        if e["name"].startswith("cnn_warm_start/"):
            rows.append([f"seed pile, {e['name'].split('/')[-1].replace(':', ' ')}", f"{e.get('contacts', 0):.0f}",
                         f"{e['cpu_time']:.0f}"] + [f"{1e3 * e[k]:.0f}" if k in e else "–"
                                                      for k in ("features_ms", "inference_ms", "gather_ms")])
    return {"name": "speed-cnn", "title": "The cnn warm start (shipped model, one thread)",
            "note": "`micro_cnn --benchmark_filter=^cnn_warm_start/default --benchmark_min_time=0.2`: CPU µs per warm start "
                    "and its parts (feature image, network inference, the gather of the forces at the contacts).",
            "columns": ["state", "contacts", "total µs", "features µs", "inference µs", "gather µs"], "rows": rows}


def block_step(ctx):
    step = gbench(ctx, "micro_step", "(BM_StepOnly(Settled)?/bodies:(1000|10000|40000)/sweeps:20/morton:(0|1|2|3)|"
                  "BM_ColoredStepOnly(Settled)?/bodies:(1000|10000|40000)/sweeps:20/morton:(0|3))$",
                  ["--benchmark_min_time=0.1"])
    us = {e["name"]: e["us_per_row"] for e in step if "us_per_row" in e}
    zero = {e["name"]: e["zero_rows"] for e in step if "zero_rows" in e}
    rows = []
    orders = [(0, "creation order"), (1, "`[bodies] order = \"morton\"`"), (2, "`internal_order = \"morton\"`"),
              (3, "`internal_order = \"auto\"`")]
    # (benchmark prefix, solver label, orders): "pgs" in every order; the default solver in creation
    # order and with every default setting, the row the per-row goal is read on.
    runs = [("", "`pgs`", orders),
            ("Colored", "`pgs-colored`", [(0, "creation order"), (3, "**default settings** (`internal_order = \"auto\"`)")])]
    for settled, pile in [("", "falling (step 150)"), ("Settled", "at rest")]:
        for prefix, solver, solver_orders in runs:
            for m, label in solver_orders:
                names = [f"BM_{prefix}StepOnly{settled}/bodies:{n}/sweeps:20/morton:{m}" for n in (1000, 10000, 40000)]
                vals = [us.get(name) for name in names]
                if None in vals:
                    continue
                free = [zero.get(name) for name in (names[0], names[2])]
                rows.append([pile, solver, label] + [f"{v:.3f}" for v in vals] + [f"{vals[2] / vals[0]:.2f}×"] +
                            ["–" if None in free else f"{100 * free[0]:.0f} / {100 * free[1]:.0f} %"])
    return {"name": "speed-step", "title": "One step per contact row against size",
            "note": "`micro_step --benchmark_filter='BM_(Colored)?StepOnly(Settled)?…/sweeps:20'` (all stages, 20 sweeps, "
                    "builtin warm start; BM_StepOnly steps with `pgs`, BM_ColoredStepOnly with the default solver "
                    "`pgs-colored`), µs per contact row (CPU time). Falling: the generated pile after 150 steps "
                    "(at 10,000 bodies and more it has not reached rest, most rows free); at rest: the same "
                    "bodies packed on the floor and settled (…StepOnlySettled). Free rows: the share of rows with "
                    "λ = 0 at 1,000 / 40,000 bodies. The default settings are pgs-colored with the internal Morton "
                    "order picked from 20,000 circles (`internal_order = \"auto\"`).",
            "columns": ["pile", "solver", "body order", "1,000 bodies", "10,000 bodies", "40,000 bodies",
                        "40,000 / 1,000", "free rows"], "rows": rows}


def block_threads(ctx):
    reps = "5"
    runs = gbench(ctx, "micro_pgs", "PgsColoredThreads/bodies:10000/sweeps:(100|1)/threads:(1|2)/assembled:0",
                  [f"--benchmark_repetitions={reps}"])
    key = lambda n: tuple(int(x) for x in re.search(r"sweeps:(\d+)/threads:(\d+)", n).groups())
    med = median_by(runs, key, "real_time")
    rows = []
    per_sweep = {t: (med[(100, t)] - med[(1, t)]) / 99 for t in (1, 2) if (100, t) in med and (1, t) in med}
    for t in sorted(per_sweep):
        rows.append([str(t), f"{med[(100, t)]:.3f}", f"{med[(1, t)]:.3f}", f"{1e3 * per_sweep[t]:.1f}"])
    if len(per_sweep) == 2:
        rows.append(["2 / 1 speed-up", f"{med[(100, 1)] / med[(100, 2)]:.2f}×", f"{med[(1, 1)] / med[(1, 2)]:.2f}×",
                     f"{per_sweep[1] / per_sweep[2]:.2f}×"])
    return {"name": "speed-threads", "title": "Threads: pgs-colored on the 10,000-body pile",
            "note": (f"`micro_pgs` BM_PgsColoredThreads, wall time, medians of {reps} repetitions (OMP_WAIT_POLICY=active). "
                     "Wall-clock speed-ups mean something only at a load average below ~1 (see the stamp)."),
            "columns": ["threads", "solve of 100 sweeps ms", "solve of 1 sweep ms", "per sweep µs"], "rows": rows}


def step_threads_block(ctx, name, title, columns):
    """An empty block of step_threads figures, marked skipped (and announced) when step_threads is not built."""
    block = {"name": name, "title": title, "columns": columns, "rows": [], "skipped": "", "note": ""}
    if not os.path.exists(ctx.bin("step_threads")):
        block["skipped"] = "step_threads not built"
        print(f"results: speed: {block['skipped']}: skipped")
    return block


def step_threads_rows(out):
    """The cells of step_threads' table rows (those starting with a body count)."""
    return [[c.strip() for c in line.strip().strip("|").split("|")]
            for line in out.splitlines() if re.match(r"\|\s*\d", line)]


def block_step_threads(ctx):
    """Whole pgs-colored steps on 1 and 2 threads (benchmarks/micro/step_threads.cpp), as users get them: the
    falling pile (1,000 and 10,000 bodies) and the 10,000 bodies packed at rest (`--at-rest`), where nearly every
    contact carries load and the sweeps weigh most."""
    rounds = "3" if not ctx.full else "7"
    runs = [("falling", ["--n", "1000,10000", "--steps", "20", "--rounds", rounds]),
            ("at rest", ["--n", "10000", "--steps", "20", "--rounds", rounds, "--at-rest"])]
    block = step_threads_block(ctx, "speed-step-threads", "Threads: whole pgs-colored steps, 1 and 2 threads",
                               ["pile", "bodies", "threads", "wall ms/step", "wall mean", "thread CPU ms/step",
                                "process CPU ms/step", "wall 1 / T"])
    if block["skipped"]:
        return block
    for pile, args in runs:
        block["rows"] += [[pile] + cells for cells in step_threads_rows(ctx.run([ctx.bin("step_threads"), *args]))]
    block["note"] = ("; ".join(f"`step_threads {' '.join(args)}`" for _, args in runs) +
                     ": micro_step's piles (falling: after 150 steps, most rows free at 10,000 bodies; at rest: "
                     "packed on the floor and settled), 20 sweeps per step, the solver's defaults "
                     "(threads only where they pay), 1 and 2 threads alternated; medians over the timed steps. "
                     "Wall-clock ratios mean something only at a load average below ~1 (see the stamp).")
    return block


def block_step_threads_load(ctx):
    """Whole steps on 1 and 2 threads with two competitor processes spinning through the rounds
    (`step_threads --load 2`): on 2 cores, the case where the second thread is worth something only
    if the step's pacer (World::kStepPays) keeps it off while it does not pay."""
    args = ["--n", "1000,10000", "--steps", "40", "--rounds", "5", "--load", "2"]
    block = step_threads_block(ctx, "speed-step-threads-load",
                               "Threads under load: whole steps, 1 and 2 threads, 2 busy competitors",
                               ["bodies", "threads", "wall ms/step", "wall mean", "thread CPU ms/step",
                                "process CPU ms/step", "wall 1 / T", "competitors' core share"])
    if block["skipped"]:
        return block
    out = ctx.run([ctx.bin("step_threads"), *args])
    share = {m.group(1): m.group(2) for m in re.finditer(r"#\s+(\d+) bodies: competitors: \d+, each got ([\d.]+)", out)}
    block["rows"] = [cells + [share.get(cells[0], "–")] for cells in step_threads_rows(out)]
    block["note"] = (f"`step_threads {' '.join(args)}`: as the block above, with two processes spinning on arithmetic "
                     "at the same nice level through the rounds (warm-up included), so that on 2 cores the step's "
                     "threads compete with them; each round starts a fresh World, whose steps go on with the pacer "
                     "the solver keeps (LcpSolver::step_pacer: warm-up included, it probes the threads 1, 2, 4, … "
                     "up to 64 steps apart while they do not pay). "
                     "Medians over the timed steps; the mean counts the pacer's threaded probes. The competitors' "
                     "share is the mean part of a core each got; the stamp's load includes them and whatever else "
                     "ran on the machine.")
    return block


def box2d3_rows(out):
    """Rows [scene, configuration, ms/step, ns/row·pass, overlap mm, moving, mean height m, ÷ quality reference,
    last column] of box2d3_compare's Markdown tables (the overlap is the largest between touching bodies at the end
    of the run: the quality side; moving: bodies faster than 0.1 m/s at the end; the ratio is to the --eq-v3
    configuration, and the row "ours at equal quality" is the program's pick by its rule)."""
    rows, scene, cols = [], "", []
    for line in out.splitlines():
        if line.startswith("## "):
            scene, cols = line[3:].split(" (load")[0], []
        elif line.startswith("|") and not line.startswith("|---"):
            cells = [c.strip() for c in line.strip().strip("|").split("|")]
            if not cols:
                cols = cells
                continue
            cell = dict(zip(cols, cells))
            ratio = next((cell[c] for c in cols if c.startswith("ms/step ÷ ") and c != "ms/step ÷ first"), "–")
            rows.append([scene, cell.get("configuration", "?"), cell.get("ms/step (median)", "?"),
                         cell.get("ns/row·pass", "?"), cell.get("overlap mm", "–"), cell.get("moving", "–"),
                         cell.get("mean height m", "–"), ratio, f"{cols[-1]}: {cells[-1]}"])
    return rows


def block_peers_v3(ctx, name="speed-peers-v3", title="Against Box2D v3", short=None, why="", always=False):
    """Box2D v3 built from source (-DBOX2D3_DIR): benchmarks/compare/box2d3_compare. `short` are the
    program's arguments when FULL is off (None: the program's defaults either way), or always with `always`."""
    block = {"name": name, "title": title, "columns": [], "rows": [], "note": "",
             "skipped": "box2d3_compare not built (configure with -DBOX2D3_DIR=<Box2D v3 sources>)"}
    if not os.path.exists(ctx.bin("box2d3_compare")):
        print(f"results: speed: {block['skipped']}: skipped")
        return block
    args = short if always else [] if ctx.full or short is None else short
    rows = box2d3_rows(ctx.run([ctx.bin("box2d3_compare"), *args]))
    block.update({"rows": rows, "skipped": "" if rows else "box2d3_compare printed no table",
                  "note": (f"`box2d3_compare {' '.join(args)}`: CPU ms per step (median), ns per row and solver pass, "
                           "the largest overlap between touching bodies at the end of the run (quality), the bodies "
                           "still moving (> 0.1 m/s) and their mean height at the end, the time ÷ Box2D v3's at 8 "
                           "substeps and 100 Hz, and the program's last column (the stack's drift, or the time "
                           "relative to the first configuration); \"ours at equal quality\" is the program's pick: "
                           "the least time per step among our configurations whose overlap and moving bodies are at most v3's at 8 substeps and "
                           "100 Hz; benchmarks/compare/README.md explains the configurations and the rule." + why),
                  "columns": ["scene", "configuration", "ms/step", "ns/row·pass", "overlap mm", "moving",
                              "mean height m", "÷ v3 8:100", "last column"]})
    return block


def block_peers_v3_10k(ctx):
    """The 10,000-body pile run 1,500 steps, with a ladder of sweeps and slops for the row "ours at equal quality":
    at 16 sweeps and the default slop our pile is still moving then (most bodies faster than 0.1 m/s: the deep
    contacts settle past the slop and Baumgarte's push keeps the bulk in motion), so the rule passes over it; the
    ladder holds settings that rest: 22 sweeps at ω = 1.2, or fewer sweeps with a slop above the pile's steady
    penetration and below v3's overlap, down to 7–8 sweeps with over-relaxation and half the default Baumgarte factor;
    the 7-sweep rungs differ only in the slop so that the table shows how close to boiling the pick is
    (benchmarks/compare/README.md)."""
    if ctx.full:
        return {"name": "speed-peers-v3-10k", "title": "Against Box2D v3, 10,000 bodies at rest", "columns": [],
                "rows": [], "note": "", "skipped": "FULL=1 runs 10,000 bodies in the block above"}
    return block_peers_v3(ctx, "speed-peers-v3-10k", "Against Box2D v3, 10,000 bodies at rest",
                          ["--n", "10000", "--rounds", "1", "--steps", "1500", "--skip-stack",
                           "--ours", "pgs-colored:16,pgs-colored:22+omega=1.2,pgs-colored:12+slop=0.012,"
                           "pgs-colored:8+slop=0.016+baumgarte=0.1+omega=1.3,pgs-colored:7+slop=0.015+baumgarte=0.1+omega=1.5,"
                           "pgs-colored:7+slop=0.016+baumgarte=0.1+omega=1.5,pgs-colored:7+slop=0.017+baumgarte=0.1+omega=1.5",
                           "--v3", "4:30,8:100"],
                          " One round (time budget); 1,500 steps, when v3's pile is at rest (the moving column says "
                          "whether ours is).")


def block_peers_v3_eq(ctx):
    """The 1,000-body pile at rest (1,500 steps; at 600 both engines' piles still move), three rounds, with a ladder
    of sweeps and contact settings for the row "ours at equal quality"."""
    return block_peers_v3(ctx, "speed-peers-v3-eq", "Against Box2D v3 at equal quality, 1,000 bodies at rest",
                          ["--n", "1000", "--rounds", "3", "--steps", "1500", "--skip-stack",
                           "--ours", "pgs-colored:6,pgs-colored:8,pgs-colored:16,pgs-colored:6+slop=0.004+omega=1.3,"
                           "pgs-colored:8+slop=0.004+omega=1.3,pgs-colored:5+slop=0.004+baumgarte=0.1+omega=1.5", "--v3", "4:30,8:100"],
                          " 1,500 steps so that both piles are at rest; slop = 0.004 m and ω = 1.3 are scene and "
                          "solver settings (`[contact] slop`, `[solver] omega`), the defaults are 0.005 m and 1.",
                          always=True)


def block_peers(ctx):
    rows, skipped = [], []
    for prog, args, what in [("box2d_compare", ["--solver", "pgs"], "Box2D 2.4.1")]:
        if not os.path.exists(ctx.bin(prog)):
            msg = f"{prog} not built ({what} not installed): skipped"
            print(f"results: speed: {msg}")
            skipped.append(msg)
            continue
        out = ctx.run([ctx.bin(prog), *args])
        for line in out.splitlines():
            if re.search(r"run CPU|ratio|per row", line):
                rows.append([what, f"`{prog} {' '.join(args)}`".replace(" `", "`"), line.strip()])
    return {"name": "speed-peers", "title": "Against Box2D 2.4.1 (seed scene)",
            "note": "The comparison programs' own summary lines." + (" " + "; ".join(skipped) + "." if skipped and rows else ""),
            "columns": ["peer", "command", "result"], "rows": rows, "skipped": "; ".join(skipped)}


def part_speed(ctx):
    """Kernels, one step, threads, peers."""
    env_before = os.environ.get("OMP_WAIT_POLICY")
    os.environ["OMP_WAIT_POLICY"] = "active"
    try:
        return [block_kernels(ctx), block_cnn(ctx), block_step(ctx), block_threads(ctx), block_step_threads(ctx),
                block_step_threads_load(ctx), block_peers(ctx),
                block_peers_v3(ctx, short=["--n", "1000", "--rounds", "1", "--pyramid", "20"],
                               why=" One round, 1,000 bodies (time budget)."),
                block_peers_v3_eq(ctx), block_peers_v3_10k(ctx)], []
    finally:
        if env_before is None:
            del os.environ["OMP_WAIT_POLICY"]
        else:
            os.environ["OMP_WAIT_POLICY"] = env_before


def part_build(ctx):
    """A clean Release build without ccache, then the test suite, in a fresh directory."""
    d = os.path.join(ctx.tmp, "build")
    shutil.rmtree(d, ignore_errors=True)
    env = {"CCACHE_DISABLE": "1"}
    times, failed = {}, []
    for label, cmd in [("configure", ["cmake", "-S", ".", "-B", d, "-DCMAKE_BUILD_TYPE=Release"]),
                       ("build", ["cmake", "--build", d, "-j", str(ctx.cores)]),
                       ("ctest", ["ctest", "--test-dir", d, "-j", str(ctx.cores), "--output-on-failure"])]:
        t0 = time.time()
        try:
            ctx.run(cmd, env=env, capture=False)
        except subprocess.CalledProcessError as e:  # a failing test still gives the times; the stamp says so
            log = os.path.join(d, "Testing", "Temporary", "LastTestsFailed.log")
            names = [ln.split(":", 1)[-1].strip() for ln in open(log)] if os.path.exists(log) else []
            failed.append(f"{label} exited with {e.returncode}" + (f" (failed: {', '.join(names)})" if names else ""))
            if label != "ctest":
                raise
        times[label] = time.time() - t0
    total = sum(times.values())
    pch = sum(os.path.getsize(p) for p in glob.glob(os.path.join(d, "**", "*.gch"), recursive=True)) / 1e6
    objs = sum(os.path.getsize(p) for p in glob.glob(os.path.join(d, "**", "*.o"), recursive=True)) / 1e6
    timing = {"name": "build-times", "title": "Build and test times (clean clone, no ccache)",
              "note": ("The steps of `make test` after the Debian packages are installed (scripts/install-deps.sh not timed), "
                       f"in a fresh build directory, `-j {ctx.cores}`, CCACHE_DISABLE=1." + (" " + "; ".join(failed) + "." if failed else "")),
              "columns": ["step", "wall"], "rows": [[k, f"{v / 60:.1f} min ({v:.0f} s)"] for k, v in times.items()]
              + [["total", f"{total / 60:.1f} min ({total:.0f} s)"]]}
    sizes = {"name": "sizes", "title": "Sizes after the build and the test suite",
             "note": "`du`-style totals of the fresh build directory (10^6 bytes).",
             "columns": ["what", "MB"],
             "rows": [["build directory", f"{mb(d):.0f}"], ["of which precompiled headers (*.gch)", f"{pch:.0f}"],
                      ["of which object files (*.o)", f"{objs:.0f}"],
                      ["`bin/deepcontact`", f"{mb(os.path.join(d, 'bin', 'deepcontact')):.1f}"]]}
    if not ctx.keep:
        shutil.rmtree(d, ignore_errors=True)
    return [timing, sizes], []


def part_python(ctx):
    """What a warm starter written in Python costs per call (benchmarks/scripts/python-starter-overhead.py)."""
    env = {"PYTHONPATH": os.path.join(ctx.build, "python")}
    probe = subprocess.run(["/usr/bin/python3", "-c", "import deepcontact"], env=dict(os.environ, **env),
                           capture_output=True, text=True)
    block = {"name": "python-starter", "title": "A warm starter written in Python", "columns": [], "rows": [],
             "note": "", "skipped": "the Python module is not built (target dc_python)"}
    if probe.returncode != 0:
        print("results: python: the module is not built (cmake --build BUILD --target dc_python): skipped")
        return [block], []
    out = ctx.run(["/usr/bin/python3", os.path.join("benchmarks", "scripts", "python-starter-overhead.py"), "--steps", "200"],
                  env=env)
    rows = []
    for line in out.splitlines():
        w = line.split()
        if len(w) == 3 and w[0] in ("zero", "py-zero", "builtin", "py-builtin"):
            lang = "Python" if w[0].startswith("py-") else "C++"
            rows.append([f"`{w[0]}` ({lang})", w[1], w[2]])
    block.update({"rows": rows, "skipped": "",
                  "note": ("Seed scene, seed 1, 200 steps: the bench times `initial_guess()` itself, so a Python starter's "
                           "warm start includes taking the GIL, building the view, the call and the conversion of its "
                           "array. `py-zero` returns `np.zeros(view.rows)`, `py-builtin` is builtin as a Python dict; the "
                           "sweeps are identical (the same guess, bit for bit). Medians of wall-clock times."),
                  "columns": ["starter", "median warm start per step µs", "median sweeps to tol"]})
    return [block], []


PARTS = {"bench": ("Default bench", part_bench),
         "solvers": ("Solver × warm start", part_solvers),
         "starters": ("Warm start × solver, prox-newton included", part_starters),
         "cholmod": ("CHOLMOD simplicial or supernodal, 10,000 bodies", part_cholmod),
         "siconos": ("Side by side with Siconos", part_siconos),
         "lcp": ("lcp solve on Siconos' test problems", part_lcp),
         "speed": ("Speed: kernels, step, threads, peers", part_speed),
         "python": ("A warm starter written in Python", part_python),
         "build": ("Build, tests and sizes", part_build)}
