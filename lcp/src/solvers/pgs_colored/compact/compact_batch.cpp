// pgs-colored's compact batches (compact_batch.hpp): the compression with its bitwise check, and
// the scalar kernel on them.
#include "solvers/pgs_colored/compact/compact_batch.hpp"

#include <bit>
#include <cstring>

#include "solvers/pgs_colored/pgs_colored_layout.hpp"
#include "solvers/pgs_colored/relax/over_relaxation.hpp"

namespace dc::colored {
namespace {

/// True when every double of a[0..n) is +0 (all bits clear: not −0).
bool all_plus_zero(const double* a, int n) {
  for (int i = 0; i < n; ++i)
    if (std::bit_cast<std::uint64_t>(a[i]) != 0) return false;
  return true;
}

template <class T, size_t N>
bool same_bits(const T (&a)[N], const T (&b)[N]) {
  return std::memcmp(a, b, sizeof(a)) == 0;
}

}  // namespace

bool compress(const Batch& B, CompactBatch& C) {
  constexpr int kept[4] = {0, 1, 2, 5};
  for (int q = 0; q < 4; ++q)
    for (int k = 0; k < W; ++k) {
      C.jn[q][k] = B.jn[kept[q]][k];
      C.jt[q][k] = B.jt[kept[q]][k];
    }
  for (int s = 0; s < 6; ++s)
    for (int k = 0; k < W; ++k) C.mjn[s][k] = B.mjn[s][k];
  std::uint8_t two = 0, fric = 0;
  for (int k = 0; k < W; ++k) {
    // A lane whose derived slots hold +0 (one body; no friction; padding) takes the zeros,
    // any other the derivation; the comparison below checks either choice.
    const double derived_j[4] = {B.jn[3][k], B.jn[4][k], B.jt[3][k], B.jt[4][k]};
    const double derived_mj[4] = {B.mjt[0][k], B.mjt[1][k], B.mjt[3][k], B.mjt[4][k]};
    if (!all_plus_zero(derived_j, 4)) two |= static_cast<std::uint8_t>(1u << k);
    if (!all_plus_zero(derived_mj, 4)) fric |= static_cast<std::uint8_t>(1u << k);
    C.mjt[0][k] = B.mjt[2][k];
    C.mjt[1][k] = B.mjt[5][k];
    C.bn[k] = B.bn[k];
    C.bt[k] = B.bt[k];
    C.mu[k] = B.mu[k];
    C.la[k] = B.la[k];
    C.lb[k] = B.lb[k];
    C.ka[k] = B.ka[k];
    C.kb[k] = B.kb[k];
  }
  C.two = two;
  C.fric = fric;
  C.count = B.count;
  Batch E;
  expand(C, E);
  return same_bits(E.jn, B.jn) && same_bits(E.mjn, B.mjn) && same_bits(E.jt, B.jt) && same_bits(E.mjt, B.mjt) &&
         same_bits(E.bn, B.bn) && same_bits(E.bt, B.bt) && same_bits(E.mu, B.mu) && same_bits(E.la, B.la) &&
         same_bits(E.lb, B.lb) && same_bits(E.ka, B.ka) && same_bits(E.kb, B.kb) && E.count == B.count;
}

bool fill_compact(const LcpProblem& p, const Eigen::Ref<const Eigen::VectorXd>& lambda, Prepared& out, int bi,
                  double* lp, double* other, double omega, bool full) {
  Batch& B = out.batches[static_cast<size_t>(bi)];
  if (full) {
    fill_batch(p, lambda, out, bi, lp, other);
    if (omega != 1.0) over_relax(B, omega);
    return false;
  }
  Batch local;  // in cache: only the compact batch goes to memory
  fill_batch(p, lambda, out, bi, lp, other, &local);
  if (omega != 1.0) over_relax(local, omega);
  if (compress(local, out.compact[static_cast<size_t>(bi)])) return true;
  B = local;
  return false;
}

void sweep_compact_scalar(const CompactBatch* batches, int b0, int b1, const double* in, double* out, double* u,
                          Acc& acc) {
  Batch B;
  for (int bi = b0; bi < b1; ++bi) {
    expand(batches[bi], B);
    sweep_scalar(&B, 0, 1, in + static_cast<long>(bi) * 2 * W, out + static_cast<long>(bi) * 2 * W, u, acc);
  }
}

}  // namespace dc::colored
