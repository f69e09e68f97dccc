#!/usr/bin/env bash
# pgs-colored on 1 and 2 OpenMP threads, 10,000-body pile (micro_pgs BM_PgsColoredThreads, the
# J-only problem the engine hands over): wall time per solve of 100 sweeps and of 1 sweep (the
# per-solve work around the sweeps: colouring, packing, Δu⁰, residual), per sweep
# ((t100 − t1) / 99), and the 2-thread speed-up of each. Several binaries (e.g. main's before a
# change and this build's) run alternated in one invocation, ROUNDS times, so load drifts hit
# both alike; the figures are medians over all repetitions. Prints the CPU model and the load
# before and after — wall-clock speed-ups mean something only when `uptime` is below ~1.
#
#   benchmarks/scripts/threads-figures.sh [MICRO_PGS ...]      (default: build/bin/micro_pgs)
#
# Environment: ROUNDS (default 3), REPS (repetitions per round, default 5), OMP_WAIT_POLICY
# (default active: spinning barriers, the right policy on free cores; passive for the CPU-time
# estimate under load, see micro_pgs.cpp).
set -euo pipefail
cd "$(dirname "$0")/../.."
BINS=("$@")
[[ ${#BINS[@]} -gt 0 ]] || BINS=(build/bin/micro_pgs)
ROUNDS=${ROUNDS:-3}
REPS=${REPS:-5}
export OMP_WAIT_POLICY=${OMP_WAIT_POLICY:-active}
OUT=$(mktemp -d)
trap 'rm -rf "$OUT"' EXIT
echo "threads-figures: CPU: $(lscpu | sed -n 's/^Model name: *//p' | head -1), $(nproc) CPUs; OMP_WAIT_POLICY=$OMP_WAIT_POLICY"
echo "threads-figures: load before: $(cut -d' ' -f1-3 /proc/loadavg)"
for round in $(seq 1 "$ROUNDS"); do
  for i in "${!BINS[@]}"; do
    "${BINS[$i]}" --benchmark_filter='PgsColoredThreads/bodies:10000/sweeps:(100|1)/threads:(1|2)/assembled:0' \
      --benchmark_repetitions="$REPS" --benchmark_format=json > "$OUT/$i.$round.json" 2> /dev/null
  done
done
echo "threads-figures: load after: $(cut -d' ' -f1-3 /proc/loadavg)"
python3 - "$OUT" "${BINS[@]}" <<'EOF'
import glob, json, re, statistics, sys
out, bins = sys.argv[1], sys.argv[2:]
print(f"{'binary':<48} {'thr':>3} | {'solve ms':>9} {'1-sweep ms':>10} {'sweep us':>9} | "
      f"{'cpu main ms':>11} {'cpu all ms':>10}")
for i, b in enumerate(bins):
    wall, cpu_main, cpu_all = {}, {}, {}
    for f in glob.glob(f"{out}/{i}.*.json"):
        for r in json.load(open(f))["benchmarks"]:
            if r.get("run_type") != "iteration":
                continue
            m = re.search(r"sweeps:(\d+)/threads:(\d+)", r["name"])
            key = (int(m.group(1)), int(m.group(2)))
            wall.setdefault(key, []).append(r["real_time"])  # ms (Unit kMillisecond)
            cpu_main.setdefault(key, []).append(r["cpu_main_ms"])
            cpu_all.setdefault(key, []).append(r["cpu_process_ms"])
    med = {k: statistics.median(v) for k, v in wall.items()}
    per_sweep = {t: (med[(100, t)] - med[(1, t)]) / 99 for t in (1, 2)}
    for t in (1, 2):
        print(f"{b[-48:]:<48} {t:>3} | {med[(100, t)]:9.3f} {med[(1, t)]:10.3f} {1e3 * per_sweep[t]:9.1f} | "
              f"{statistics.median(cpu_main[(100, t)]):11.3f} {statistics.median(cpu_all[(100, t)]):10.3f}")
    # CPU-time estimate of the 2-thread speed-up on two free cores (OMP_WAIT_POLICY=passive):
    # 1-thread CPU / the busier thread's CPU (calling thread or the other one).
    cm = {k: statistics.median(v) for k, v in cpu_main.items()}
    ca = {k: statistics.median(v) for k, v in cpu_all.items()}
    est = {s: cm[(s, 1)] / max(cm[(s, 2)], ca[(s, 2)] - cm[(s, 2)]) for s in (100, 1)}
    print(f"{'':<48} 2/1 | {med[(100, 1)] / med[(100, 2)]:8.2f}x {med[(1, 1)] / med[(1, 2)]:9.2f}x "
          f"{per_sweep[1] / per_sweep[2]:8.2f}x |  wall speed-ups; {len(wall[(100, 1)])} repetitions")
    print(f"{'':<48} cpu | {est[100]:8.2f}x {est[1]:9.2f}x {'':>9} |  CPU-time estimate (meaningful with passive waiting)")
EOF
