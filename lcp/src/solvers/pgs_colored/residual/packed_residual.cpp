// pgs-colored's packed closing residual over the batches (packed_residual.hpp).
#include "solvers/pgs_colored/residual/packed_residual.hpp"

#include <algorithm>
#include <vector>

#include "dc/core/work_team.hpp"

namespace dc::colored {

ResidualAcc packed_residual(const Prepared& prep, const double* lam, double omega, const ResidualKernels& k,
                            int threads) {
  const int nb = static_cast<int>(prep.batches.size()), np = static_cast<int>(prep.pairs.size());
  const double* diag = prep.diag.data();
  const double* u = prep.du.data();
  auto run = [&](int b0, int b1, ResidualAcc& acc) {  // items [b0, b1): batches, then pair batches
    if (b0 < nb) k.single(prep.batches.data(), b0, std::min(b1, nb), lam, diag, u, omega, acc);
    if (b1 > nb)
      k.pairs(prep.pairs.data(), std::max(b0, nb) - nb, b1 - nb, lam + prep.pair_base, diag + prep.pair_base, u,
              omega, acc);
  };
  ResidualAcc acc;
  const int items = nb + np;
  if (threads <= 1) {
    run(0, items, acc);
    return acc;
  }
  constexpr int kChunk = 64;  // batches per work item
  const int chunks = (items + kChunk - 1) / kChunk;
  struct alignas(64) Part {
    ResidualAcc acc;
  };
  std::vector<Part> parts(static_cast<size_t>(chunks));
  calling_thread_team().for_parts(threads, chunks, [&](int c) {
    run(c * kChunk, std::min(items, (c + 1) * kChunk), parts[static_cast<size_t>(c)].acc);
  });
  for (const Part& p : parts) {
    acc.r = max_of(acc.r, p.acc.r);
    acc.nan = acc.nan || p.acc.nan;
  }
  return acc;
}

}  // namespace dc::colored
