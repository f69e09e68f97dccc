#pragma once
// Private to "pgs-colored" (dc/lcp/pgs_colored.hpp): software prefetch of the packing's sources.
// The pack visits the contacts in colour order, which strides across the contact, J, b, λ⁰ and
// body arrays (each colour's contacts are spread over the whole problem), so nearly every source
// of a lane is a cache miss, and its addresses hang on each other: the contact gives the rows and
// bodies, the row its first J entry (the outer index), that entry the values. A lane's own loads
// run one chain after another; the prefetches below walk the chains of later lanes ahead of the
// pack, one link per stage, so those misses overlap. Hints only: nothing is read that the pack
// would not read, and no result depends on them.
#include <cstddef>

#include "dc/lcp/lcp_problem.hpp"

namespace dc::colored {

/// Ordered lanes ahead of the one being packed at which each stage is issued: the contact record
/// first, its rows' outer index, b, λ⁰ and bodies next, the J entries last (one batch of W = 8
/// lanes between stages: a stage's lines arrive before the next stage reads them).
constexpr int kPrefetchContact = 24;
constexpr int kPrefetchRows = 16;
constexpr int kPrefetchEntries = 8;

/// The prefetches of ordered lane s (order = the lead contacts by ordered lane, n of them):
/// stage 1 for lane s + kPrefetchContact, stage 2 for s + kPrefetchRows, stage 3 for
/// s + kPrefetchEntries. `lambda`: λ⁰ in row order; `dynamic`, `slot`: per body (Prepared's).
/// Always inlined: GCC takes a function that only prefetches for one without side effects
/// ("pure", returning nothing) and drops its calls.
#if defined(__GNUC__)
__attribute__((always_inline))
#endif
inline void prefetch_sources(const LcpProblem& p, const double* lambda, const unsigned char* dynamic,
                             const int* slot, const int* order, int n, int s) {
#if defined(__GNUC__)
  const ContactConstraint* cons = p.constraints.contacts().data();
  if (s + kPrefetchContact < n) __builtin_prefetch(cons + order[s + kPrefetchContact]);
  const int* outer = p.J.outerIndexPtr();
  if (s + kPrefetchRows < n) {
    const ContactConstraint& k = cons[order[s + kPrefetchRows]];
    __builtin_prefetch(outer + k.normal_row);
    __builtin_prefetch(p.b.data() + k.normal_row);
    __builtin_prefetch(lambda + k.normal_row);
    if (k.tangent_row >= 0) {  // (usually the next row: the same lines)
      __builtin_prefetch(outer + k.tangent_row);
      __builtin_prefetch(p.b.data() + k.tangent_row);
      __builtin_prefetch(lambda + k.tangent_row);
    }
    for (const int body : {k.body_a, k.body_b}) {
      if (body < 0) continue;
      __builtin_prefetch(p.inv_mass.data() + 3 * body);
      __builtin_prefetch(p.inv_mass.data() + 3 * body + 2);
      __builtin_prefetch(dynamic + body);
      __builtin_prefetch(slot + body);
    }
  }
  if (s + kPrefetchEntries < n) {
    const ContactConstraint& k = cons[order[s + kPrefetchEntries]];
    for (const int row : {k.normal_row, k.tangent_row}) {
      if (row < 0) continue;
      const std::ptrdiff_t q0 = outer[row];
      __builtin_prefetch(p.J.valuePtr() + q0);
      __builtin_prefetch(p.J.valuePtr() + q0 + 5);
      __builtin_prefetch(p.J.innerIndexPtr() + q0);
      __builtin_prefetch(p.J.innerIndexPtr() + q0 + 5);
    }
  }
#else
  (void)p, (void)lambda, (void)dynamic, (void)slot, (void)order, (void)n, (void)s;
#endif
}

}  // namespace dc::colored
