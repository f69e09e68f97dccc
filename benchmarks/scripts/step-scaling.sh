#!/usr/bin/env bash
# Step cost against scene size (linear is the target, docs/design.md §8.4): the seed scene family scaled
# to n circles at the seed's density — box side 30·√(n/100) = 3√n m, Gaussian mean at the
# centre, σ = 4.65·√(n/100) m — simulated for STEPS steps with the builtin warm start and
# SWEEPS fixed PGS sweeps. Prints, per (n, sweeps), the mean LCP rows per step, the mean
# milliseconds per step of each stage of World::step (collide, of which broad phase;
# assemble, warm start, solve, integrate) and of the trajectory recorder (record), the
# total, and the cost per contact row and step (total / rows) with its ratio to the first n.
# Times are wall clock (StepProfile, steady_clock), so run it on a quiet machine; the
# process CPU time per row-step is printed next to them as a cross-check under load.
#
#   benchmarks/scripts/step-scaling.sh [BUILD_DIR]                 (default: build)
#
# Environment: SIZES (default "1000 2500 10000 40000"), SWEEPS (default "20 1"),
# STEPS (default 150), WARMSTART (default builtin), ORDERS (default "creation"; "creation
# morton" runs each size with the generated bodies in creation order and then numbered in
# Morton order, `[bodies] order`, side by side; "internal" runs the creation numbering with the
# engine-internal re-sorted order `[bodies] internal_order = "morton"`; the ratio is to the
# first size of the same order).
set -euo pipefail
cd "$(dirname "$0")/../.."
BUILD=${1:-build}
DC="$BUILD/bin/deepcontact"
SIZES=${SIZES:-"1000 2500 10000 40000"}
SWEEPS=${SWEEPS:-"20 1"}
STEPS=${STEPS:-150}
WARMSTART=${WARMSTART:-builtin}
ORDERS=${ORDERS:-creation}
[[ -x "$DC" ]] || { echo "step-scaling: $DC not found (cmake --build $BUILD --target deepcontact)" >&2; exit 2; }

echo "step-scaling: CPU: $(lscpu | sed -n 's/^Model name: *//p' | head -1); load: $(cut -d' ' -f1-3 /proc/loadavg)"
echo "step-scaling: git $(git rev-parse --short HEAD 2>/dev/null || echo '?'), $STEPS steps, warm start $WARMSTART"
printf '%8s %6s %6s %8s | %8s %8s %8s %8s %8s %8s %8s | %8s | %9s %6s | %9s\n' \
  order sweeps n rows collide broad assemble warm solve integr record total "us/row" ratio "cpu us/row"
for sw in $SWEEPS; do
  declare -A first=()
  for n in $SIZES; do
   for order in $ORDERS; do
    read -r side mean sigma < <(awk -v n="$n" 'BEGIN { s = 3 * sqrt(n); printf "%.6f %.6f %.6f\n", s, s / 2, 0.465 * sqrt(n) }')
    line=$("$DC" simulate --set "world.width=$side" --set "world.height=$side" --set "bodies.count=$n" \
      --set "bodies.mean=[$mean,$mean]" --set "bodies.sigma=$sigma" --set "solver.sweeps=$sw" \
      --set "bodies.order=${order/internal/creation}" \
      --set "bodies.internal_order=$([[ $order == internal ]] && echo morton || echo none)" \
      --steps "$STEPS" --warmstart "$WARMSTART" --profile | grep '^profile ')
    # "profile key=value ..." (apps/deepcontact/commands/simulate_command.cpp): mean ms per step of each stage.
    get() { sed -n "s/.* $1=\([^ ]*\).*/\1/p" <<< "$line"; }
    rows=$(get rows); total=$(get total_ms)
    us=$(awk -v t="$total" -v r="$rows" 'BEGIN { printf "%.4f", (r > 0 ? 1000 * t / r : 0) }')
    cpu_us=$(awk -v c="$(get cpu_s)" -v s="$(get steps)" -v r="$rows" \
      'BEGIN { printf "%.4f", (r > 0 ? 1e6 * c / (s * r) : 0) }')
    [[ -n "${first[$order]:-}" ]] || first[$order]=$us
    ratio=$(awk -v a="$us" -v b="${first[$order]}" 'BEGIN { printf "%.3f", a / b }')
    printf '%8s %6s %6s %8.0f | %8.3f %8.3f %8.3f %8.3f %8.3f %8.3f %8.3f | %8.3f | %9s %6s | %9s\n' \
      "$order" "$sw" "$n" "$rows" "$(get collide_ms)" "$(get broad_phase_ms)" "$(get assemble_ms)" "$(get warm_start_ms)" \
      "$(get solve_ms)" "$(get integrate_ms)" "$(get record_ms)" "$total" "$us" "$ratio" "$cpu_us"
   done
  done
done
