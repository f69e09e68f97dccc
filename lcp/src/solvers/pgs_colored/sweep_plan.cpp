#include "solvers/pgs_colored/sweep_plan.hpp"

namespace dc::colored {
namespace {

/// True when range rg is swept by the scalar kernel: one batch with at most `lanes` lanes in use,
/// or the overflow set (one contact or manifold per batch).
bool scalar_range(const Prepared& prep, const Range& rg, int lanes) {
  if (lanes <= 0 || rg.end <= rg.begin) return false;
  if (rg.serial) return true;
  if (rg.end - rg.begin != 1) return false;
  const int count = rg.pairs         ? prep.pairs[static_cast<size_t>(rg.begin)].count
                    : prep.compact_on ? prep.compact[static_cast<size_t>(rg.begin)].count
                                      : prep.batches[static_cast<size_t>(rg.begin)].count;
  return count <= lanes;
}

}  // namespace

void plan_sweep(const Prepared& prep, int scalar_lanes, std::vector<SweepStep>& out) {
  out.clear();
  for (const Range& rg : prep.ranges) {
    if (rg.end <= rg.begin) continue;
    const bool scalar = scalar_range(prep, rg, scalar_lanes);
    if (scalar && !out.empty()) {
      SweepStep& last = out.back();
      if (last.scalar && last.pairs == rg.pairs && last.end == rg.begin) {
        last.end = rg.end;  // the next colour's batches follow: one call, the same order
        continue;
      }
    }
    out.push_back({rg.begin, rg.end, rg.pairs, scalar});
  }
}

}  // namespace dc::colored
