// pgs-colored's packed closing residual over the batches (packed_residual.hpp).
#include "solvers/pgs_colored/residual/packed_residual.hpp"

#include <algorithm>
#include <vector>

#include "dc/core/work_team.hpp"

namespace dc::colored {

ResidualAcc packed_residual(const Prepared& prep, const double* lam, double omega, const ResidualKernels& k,
                            int threads, double* lambda_out) {
  const int nb = static_cast<int>(prep.batches.size()), np = static_cast<int>(prep.pairs.size());
  const double* diag = prep.diag.data();
  const double* u = prep.du.data();
  const int* row_of = prep.row_of.data();
  // Item b's first slot (items: batches, then pair batches, whose slots follow on).
  auto slot = [&](int b) { return b < nb ? 2 * W * b : prep.pair_base + 4 * W * (b - nb); };
  auto run = [&](int b0, int b1, ResidualAcc& acc) {  // items [b0, b1), then their λ in row order
    if (b0 < nb && !prep.compact_on) k.single(prep.batches.data(), b0, std::min(b1, nb), lam, diag, u, omega, acc);
    if (b0 < nb && prep.compact_on && k.compact != nullptr)
      k.compact(prep.compact.data(), b0, std::min(b1, nb), lam, diag, u, omega, acc);
    if (b0 < nb && prep.compact_on && k.compact == nullptr) {
      // The compact batches' rows expanded in cache (expand_rows), 8 at a time, for the kernel
      // on full batches (it reads each expanded batch after the next ones were written).
      constexpr int kGroup = 8;
      Batch full[kGroup];
      for (int g = b0; g < std::min(b1, nb); g += kGroup) {
        const int n = std::min(kGroup, std::min(b1, nb) - g);
        for (int q = 0; q < n; ++q) expand_rows(prep.compact[static_cast<size_t>(g + q)], full[q]);
        k.single(full, 0, n, lam + 2 * W * g, diag + 2 * W * g, u, omega, acc);
      }
    }
    if (b1 > nb)
      k.pairs(prep.pairs.data(), std::max(b0, nb) - nb, b1 - nb, lam + prep.pair_base, diag + prep.pair_base, u,
              omega, acc);
    for (int s = slot(b0), end = slot(b1); s < end; ++s)
      if (const int row = row_of[s]; row >= 0) lambda_out[row] = lam[s];
  };
  constexpr int kChunk = 64;  // batches per work item (their λ still in cache for the permutation)
  const int items = nb + np;
  const int chunks = (items + kChunk - 1) / kChunk;
  ResidualAcc acc;
  if (threads <= 1) {
    for (int c = 0; c < chunks; ++c) run(c * kChunk, std::min(items, (c + 1) * kChunk), acc);
    return acc;
  }
  struct alignas(64) Part {
    ResidualAcc acc;
  };
  // Each chunk's accumulator, combined in chunk order below (the same bits whatever the schedule):
  // on the stack up to kStackChunks chunks (16 KB; 16,384 batches), so that a solve allocates
  // nothing here.
  constexpr int kStackChunks = 256;
  Part on_stack[kStackChunks];
  std::vector<Part> on_heap;
  Part* parts = on_stack;
  if (chunks > kStackChunks) {
    on_heap.resize(static_cast<size_t>(chunks));
    parts = on_heap.data();
  }
  calling_thread_team().for_parts(threads, chunks, [&](int c) {
    run(c * kChunk, std::min(items, (c + 1) * kChunk), parts[c].acc);
  });
  for (int c = 0; c < chunks; ++c) {
    acc.r = max_of(acc.r, parts[c].acc.r);
    acc.nan = acc.nan || parts[c].acc.nan;
  }
  return acc;
}

}  // namespace dc::colored
