// pgs-colored's pack on the calling thread's team (team_pack.hpp).
#include "solvers/pgs_colored/setup/team_pack.hpp"

#include <algorithm>
#include <atomic>

#include "solvers/pgs_colored/compact/compact_batch.hpp"
#include "solvers/pgs_colored/relax/over_relaxation.hpp"

namespace dc::colored {

void pack_parts(const std::vector<Range>& ranges, int batches, int threads, int chunk, std::vector<PackPart>& parts) {
  const int nt = std::max(1, threads);
  const int step = std::max(1, chunk);
  parts.clear();
  for (int t = 0; t < nt; ++t)
    for (const Range& rg : ranges) {
      const long n = rg.end - rg.begin;
      const int lo = rg.begin + static_cast<int>(n * t / nt), hi = rg.begin + static_cast<int>(n * (t + 1) / nt);
      const int off = rg.pairs ? batches : 0;
      for (int b = lo; b < hi; b += step) parts.push_back({off + b, off + std::min(hi, b + step)});
    }
}

void pack_batches(const LcpProblem& p, const Eigen::Ref<const Eigen::VectorXd>& lambda, double omega, bool compact,
                  Prepared& prep, double* lp, double* other, int threads, const PartJob* side, int stage_from) {
  const int nb = static_cast<int>(prep.batches.size());
  const int jobs = nb + static_cast<int>(prep.pairs.size());  // batches, then pair batches
  if (compact) prep.compact.resize(static_cast<size_t>(nb));
  // The compact layout when every batch compresses exactly; after the first that does not, the
  // batches are packed full (and those packed compact before it again, below).
  std::atomic<bool> inexact{!compact};
  auto fill = [&](int bi) {
    if (bi < nb) {
      if (!fill_compact(p, lambda, prep, bi, lp, other, omega, inexact.load(std::memory_order_relaxed)))
        inexact.store(true, std::memory_order_relaxed);
    } else {
      fill_pair(p, lambda, prep, bi - nb, lp, other);
      if (omega != 1.0) over_relax(prep.pairs[static_cast<size_t>(bi - nb)], omega);
    }
  };
  stage_sources(p, lambda, prep, stage_from, threads);
  if (threads <= 1) {  // (no team run: in job order)
    if (side != nullptr) (*side)(0);
    for (int bi = 0; bi < jobs; ++bi) fill(bi);
  } else {
    pack_parts(prep.ranges, nb, threads, kPackChunk, prep.pack_parts);
    const int first = side != nullptr ? 1 : 0;
    const int parts = first + static_cast<int>(prep.pack_parts.size());
    calling_thread_team().for_parts(threads, parts, [&](int part) {
      if (part < first) return (*side)(0);
      const PackPart& q = prep.pack_parts[static_cast<size_t>(part - first)];
      for (int bi = q.begin; bi < q.end; ++bi) fill(bi);
    });
  }
  prep.compact_on = !inexact.load(std::memory_order_relaxed);
  if (compact && !prep.compact_on)  // (a problem not of the engine's form: rare, serial)
    for (int bi = 0; bi < nb; ++bi) (void)fill_compact(p, lambda, prep, bi, lp, other, omega, true);
}

}  // namespace dc::colored
