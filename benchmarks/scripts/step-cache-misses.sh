#!/usr/bin/env bash
# Cache misses of one step against scene size and body order, where the CPU's counters are not
# available (this VM: `perf stat -e cache-misses` is "not supported"): callgrind simulates the
# caches on `micro_step`'s BM_Step (the settled pile of the seed family, 20 sweeps; micro_step.cpp)
# and the table takes the cost of the one measured World::step (callgrind's BM_Step → World::step
# call; the 150 settling steps are called from elsewhere). Simulated: L1d 32 KiB and a last level
# of 1 MiB, 8-way, 64-byte lines — Zen 4's per-core L2 —, no hardware prefetcher, so a streaming
# pass counts a miss per line that a real core would have prefetched: read the counts as "lines
# that come from beyond L2", not as stall time.
#
#   benchmarks/scripts/step-cache-misses.sh [BUILD_DIR]    (default: build-portable)
#
# BUILD_DIR must be a portable build with the micro benchmarks (valgrind 3.19 cannot run AVX-512
# code): cmake -S . -B build-portable -DDC_NATIVE=OFF && cmake --build build-portable --target micro_step
# Environment: SIZES (default "1000 40000"), ORDERS (default "0 1": creation, Morton numbering).
# Takes ≈ 2 min per 1,000-body run and ≈ 7 min per 40,000-body run.
set -euo pipefail
cd "$(dirname "$0")/../.."
BUILD=${1:-build-portable}
BIN="$BUILD/bin/micro_step"
SIZES=${SIZES:-"1000 40000"}
ORDERS=${ORDERS:-"0 1"}
[[ -x "$BIN" ]] || { echo "step-cache-misses: $BIN not found (see the header of this script)" >&2; exit 2; }
command -v valgrind >/dev/null || { echo "step-cache-misses: valgrind not found" >&2; exit 2; }
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT

echo "step-cache-misses: CPU: $(lscpu | sed -n 's/^Model name: *//p' | head -1); git $(git rev-parse --short HEAD 2>/dev/null || echo '?')"
printf '%-8s %-8s %8s %12s %14s %16s\n' bodies order rows "instr/row" "L1d miss/row" "L2 (1 MiB) miss/row"
for n in $SIZES; do
  for m in $ORDERS; do
    out="$tmp/$n.$m"
    nice valgrind --tool=callgrind --cache-sim=yes --D1=32768,8,64 --I1=32768,8,64 --LL=1048576,8,64 \
      --callgrind-out-file="$out.cg" "$BIN" --benchmark_filter="BM_Step/bodies:$n/sweeps:20/morton:$m\$" \
      --benchmark_min_time=0 >"$out.txt" 2>&1 || { echo "step-cache-misses: valgrind failed, see:" >&2; tail -5 "$out.txt" >&2; exit 1; }
    rows=$(grep -oE 'rows=[0-9.]+k?' "$out.txt" | head -1 | sed 's/rows=//')
    case $rows in *k) rows=$(awk -v r="${rows%k}" 'BEGIN { printf "%d", r * 1000 + 0.5 }') ;; esac
    # Events: Ir Dr Dw I1mr D1mr D1mw ILmr DLmr DLmw. The block of BM_Step lists its callees.
    callgrind_annotate --inclusive=yes --tree=calling "$out.cg" 2>/dev/null | awk -v rows="$rows" -v n="$n" -v m="$m" '
      /\* .*BM_Step/ { in_step = 1; next }
      in_step && /dc::World::step/ {
        gsub(/\([^)]*%\)/, ""); gsub(/,/, "")
        printf "%-8s %-8s %8d %12.0f %14.1f %16.1f\n", n, (m == 1 ? "morton" : "creation"), rows,
               $1 / rows, ($5 + $6) / rows, ($8 + $9) / rows
        exit
      }
      /^$/ { in_step = 0 }'
  done
done
