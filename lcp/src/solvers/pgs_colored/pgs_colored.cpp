// "pgs-colored": colour-ordered matrix-free PGS, 8 contacts per lane group
// (dc/lcp/pgs_colored.hpp), after Box2D v3's graph-coloured solver, in double precision
// with "pgs"'s row form (J_i / A_ii pre-scaled, the same FMAs and tree sums). This file: the
// set-up (input checks, colouring, packing into batches) and the sweep driver; the kernels
// are pgs_colored_{scalar,avx2,avx512}.cpp, the layout is pgs_colored_batch.hpp. λ lives in a
// permuted vector during the sweeps (per batch 8 λ_n, then 8 λ_t) and is mapped back at
// checkpoints and at the end. With threads each batch is written by one thread from its own
// inputs, so the result depends neither on the thread count nor on the schedule. A sweep does
// nothing but the kernel: λ^{k−1} and λ^k live in two buffers (run_sweeps_double_buffered)
// and the Δu finiteness check is fused into the kernels. Design: docs/lcp.md "`pgs-colored`".
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <exception>
#include <limits>
#include <string>
#include <utility>
#include <vector>

#if defined(_OPENMP)
#include <omp.h>
#endif

#include "dc/core/error.hpp"
#include "dc/lcp/pgs_colored.hpp"
#include "solvers/pgs_colored/contact_coloring.hpp"
#include "solvers/pgs_colored/pgs_colored_batch.hpp"
#include "solvers/pgs_colored/pgs_colored_input.hpp"
#include "solvers/pgs_colored/pgs_colored_products.hpp"
#include "solvers/solver_common.hpp"
#include "solvers/solvers.hpp"

namespace dc {
namespace {

using colored::Batch;
using colored::kStride;
using colored::W;
using solvers::finish;
using solvers::settle_status;
using solvers::StopRule;

/// Batches [begin, end) of one colour (independent: may run in any order or in parallel),
/// or of the overflow set (serial = true: one contact per batch, in order).
struct Range {
  int begin, end;
  bool serial;
};

/// The packed problem and the solve's buffers; kept by the solver between solves.
struct Prepared {
  std::vector<Batch> batches;
  std::vector<Range> ranges;
  std::vector<int> row_of;    // permuted slot → LCP row (−1: padding or no tangent row)
  std::vector<int> order;     // contact of each lane, colour after colour
  std::vector<int> start;     // first lane of each colour (overflow last)
  std::vector<int> batch_of;  // first batch of each colour
  std::vector<std::uint8_t> dynamic;
  std::vector<int> failed;    // per batch: its first contact that cannot be packed, or −1
  std::vector<double, Eigen::aligned_allocator<double>> du;
  Eigen::VectorXd jt;    // Jᵀλ (scratch of the products, pgs_colored_products.hpp)
  int body_entries = 0;  // kStride·bodies; the zero body follows
  std::uint64_t generation = 0;  // the colouring (ContactColoring::generation) laid out; 0: none
};

/// Packs row i of J on the bodies at J columns a (slots 0–2) and bb (slots 3–5; −1 absent) into
/// lane `lane` of j/mj, unscaled: j = J_i, mj = M⁻¹ J_iᵀ Δt, b = b_i, diag = A_ii (summed in slot
/// order as "pgs"'s pack_row); scale_rows divides by A_ii afterwards, 8 lanes at once. False
/// when the row acts on another body.
bool pack_row(const LcpProblem& p, int i, int a, int bb, double (*j)[W], double (*mj)[W], double* b, double* diag,
              int lane) {
  double r[6] = {0, 0, 0, 0, 0, 0};
  // The usual storage (what the engine assembles): the columns a, a+1, a+2 (, bb, bb+1, bb+2)
  // once each, in order; then each r_s is 0 + J_is, as the general loop below sums it (−0 → +0).
  const double* value = p.J.valuePtr();
  const int q0 = p.J.outerIndexPtr()[i];
  const int n = (p.J.isCompressed() ? p.J.outerIndexPtr()[i + 1] : q0 + p.J.innerNonZeroPtr()[i]) - q0;
  const int* col = p.J.innerIndexPtr() + q0;
  if (n == (bb < 0 ? 3 : 6) && col[0] == a && col[1] == a + 1 && col[2] == a + 2 &&
      (bb < 0 || (col[3] == bb && col[4] == bb + 1 && col[5] == bb + 2))) {
    for (int s = 0; s < n; ++s) r[s] = 0.0 + value[q0 + s];
  } else {
    for (SparseRowMatrix::InnerIterator it(p.J, i); it; ++it) {
      const int c = static_cast<int>(it.col());
      if (c >= a && c < a + 3) {
        r[c - a] += it.value();
      } else if (bb >= 0 && c >= bb && c < bb + 3) {
        r[3 + c - bb] += it.value();
      } else {
        return false;
      }
    }
  }
  const double* im = p.inv_mass.data();
  double d = 0.0;
  for (int s = 0; s < 6; ++s) {
    const int off = s < 3 ? a : bb;
    const double m = off < 0 ? 0.0 : r[s] * im[off + s % 3] * p.dt;
    if (off >= 0) d += r[s] * m;
    j[s][lane] = r[s];
    mj[s][lane] = m;
  }
  b[lane] = p.b[i];
  diag[lane] = d;
  return true;
}

/// j ← j/A_ii and b ← b/A_ii on all lanes (padding lanes: A_ii = 1, zero rows); false when a
/// lane's A_ii is not > 0 or 1/A_ii is not finite. The same products as a lane-by-lane scaling.
bool scale_rows(double (*j)[W], double* b, const double* diag) {
  double inv[W];
  bool ok = true;
  for (int lane = 0; lane < W; ++lane) {
    inv[lane] = 1.0 / diag[lane];
    ok &= diag[lane] > 0 && std::isfinite(inv[lane]);
  }
  for (int s = 0; s < 6; ++s)
    for (int lane = 0; lane < W; ++lane) j[s][lane] *= inv[lane];
  for (int lane = 0; lane < W; ++lane) b[lane] *= inv[lane];
  return ok;
}

/// Packs contact c into lane `lane` of B (rows unscaled, see pack_row); false when one of its
/// rows acts on another body.
bool pack_contact(const LcpProblem& p, const std::vector<std::uint8_t>& dynamic, int zero, int c, Batch& B, int lane,
                  int* row_of, double* diag_n, double* diag_t) {
  const ContactConstraint& k = p.constraints[c];
  const int first = k.has_body_a() ? std::min(k.body_a, k.body_b) : k.body_b;
  const int second = k.has_body_a() ? std::max(k.body_a, k.body_b) : -1;
  const int a = 3 * first, bb = second < 0 ? -1 : 3 * second;  // columns of J
  if (!pack_row(p, k.normal_row, a, bb, B.jn, B.mjn, B.bn, diag_n, lane)) return false;
  if (k.has_friction()) {
    if (!pack_row(p, k.tangent_row, a, bb, B.jt, B.mjt, B.bt, diag_t, lane)) return false;
    B.mu[lane] = k.mu;
  } else {
    for (int s = 0; s < 6; ++s) B.jt[s][lane] = B.mjt[s][lane] = 0.0;
    B.bt[lane] = B.mu[lane] = 0.0;
    diag_t[lane] = 1.0;
  }
  const bool da = dynamic[static_cast<size_t>(first)] != 0;
  const bool db = second >= 0 && dynamic[static_cast<size_t>(second)] != 0;
  B.la[lane] = da ? kStride * first : zero;
  B.lb[lane] = db ? kStride * second : zero;
  B.ka[lane] = da ? 1 : 0;
  B.kb[lane] = db ? 1 : 0;
  row_of[lane] = k.normal_row;
  row_of[W + lane] = k.tangent_row;
  return true;
}

/// Zero coefficients, the zero body and no stores for lanes [from, W) of B (padding).
void pad(Batch& B, int from, int zero, int* row_of) {
  for (int lane = from; lane < W; ++lane) {
    for (int s = 0; s < 6; ++s) B.jn[s][lane] = B.mjn[s][lane] = B.jt[s][lane] = B.mjt[s][lane] = 0.0;
    B.bn[lane] = B.bt[lane] = B.mu[lane] = 0.0;
    B.la[lane] = B.lb[lane] = zero;
    B.ka[lane] = B.kb[lane] = 0;
    row_of[lane] = row_of[W + lane] = -1;
  }
}

/// Orders the contacts by colour and lays out the batches (O(contacts), the colouring and the
/// counting sort on `threads` threads; the same layout for every thread count). Returns an
/// error (the reason "pgs" runs instead) when a normal row has bounds other than [0, ∞).
std::string layout(const LcpProblem& p, ContactColorer& colorer, int threads, Prepared& out) {
  const ContactConstraints& cons = p.constraints;
  if (cons.empty() || cons.rows() != p.rows()) return "no contact constraints";
  const int bodies = static_cast<int>(p.J.cols() / 3) + (p.J.cols() % 3 != 0 ? 1 : 0);
  out.body_entries = kStride * bodies;
  out.dynamic.assign(static_cast<size_t>(bodies), 0);
  const int ncols = static_cast<int>(p.inv_mass.size());
  for (int c = 0; c < ncols; ++c)
    if (p.inv_mass[c] != 0.0) out.dynamic[static_cast<size_t>(c / 3)] = 1;
  for (int c = 0; c < cons.size(); ++c) {
    const int i = cons[c].normal_row;
    if (p.is_friction_row(i) || p.lo[i] != 0.0 || p.hi[i] != std::numeric_limits<double>::infinity())
      return "contact " + std::to_string(c) + "'s normal row has bounds other than [0, inf)";
  }
  const ContactColoring& col = colorer.color(cons, out.dynamic, threads);
  if (col.repeated && col.generation == out.generation) {
    // The colours of the layout in `out` (same contacts, same order): order, ranges and sizes
    // stand; the batches are refilled from this problem's J, b and λ⁰ (fill_batch).
    out.failed.assign(out.batches.size(), -1);
    return {};
  }
  out.generation = col.generation;
  // Contacts per colour (counting sort, contact order kept inside a colour), overflow last. With
  // threads: each thread counts and places one contiguous block of contacts, at offsets that
  // put the blocks of a colour in block order: the stable order, whatever the thread count.
  const int nc = cons.size(), ncol = col.colors;
  const int slots = ncol + 1;
  auto slot_of = [&](int colour) { return colour == ContactColoring::kOverflow ? ncol : colour; };
  const int parts = std::max(1, std::min(threads, nc / 4096));
  std::vector<int> count(static_cast<size_t>(parts) * slots, 0);  // count[part·slots + slot]
  std::vector<int>& start = out.start;
  start.assign(static_cast<size_t>(ncol) + 2, 0);
  out.order.resize(static_cast<size_t>(nc));
  out.batch_of.assign(static_cast<size_t>(ncol) + 2, 0);
  const int* colour_of = col.color.data();
#pragma omp parallel num_threads(parts) if (parts > 1)
  {
#if defined(_OPENMP)
    const int part = omp_get_thread_num();
#else
    const int part = 0;
#endif
    const int lo = static_cast<int>(static_cast<long long>(nc) * part / parts);
    const int hi = static_cast<int>(static_cast<long long>(nc) * (part + 1) / parts);
    int* mine = count.data() + static_cast<size_t>(part) * slots;
    for (int c = lo; c < hi; ++c) ++mine[slot_of(colour_of[c])];
#pragma omp barrier
#pragma omp single
    {
      // count[part·slots + k] ← the first position of part's contacts of slot k.
      int at = 0;
      for (int k = 0; k < slots; ++k) {
        start[static_cast<size_t>(k)] = at;
        for (int q = 0; q < parts; ++q) {
          const int n = count[static_cast<size_t>(q) * slots + k];
          count[static_cast<size_t>(q) * slots + k] = at;
          at += n;
        }
      }
      start[static_cast<size_t>(slots)] = at;
    }
    for (int c = lo; c < hi; ++c) out.order[static_cast<size_t>(mine[slot_of(colour_of[c])]++)] = c;
  }
  out.ranges.clear();
  int b = 0;
  for (int k = 0; k <= ncol; ++k) {
    out.batch_of[static_cast<size_t>(k)] = b;
    const int n = start[static_cast<size_t>(k) + 1] - start[static_cast<size_t>(k)];
    const bool overflow = k == ncol;
    const int nb = overflow ? n : (n + W - 1) / W;
    if (nb > 0) out.ranges.push_back({b, b + nb, overflow});
    b += nb;
  }
  out.batch_of[static_cast<size_t>(ncol) + 1] = b;
  out.batches.resize(static_cast<size_t>(b));  // reused storage: every lane is written below
  out.row_of.resize(static_cast<size_t>(b) * 2 * W);
  out.failed.assign(static_cast<size_t>(b), -1);
  return {};
}

/// Fills batch `bi` (colour slot k) from the ordered contacts and its 2·W entries of the permuted
/// λ⁰ (lp and other; 0 for padding); records in out.failed[bi] the first of its contacts whose
/// rows cannot be packed (another body, A_ii not > 0).
void fill_batch(const LcpProblem& p, const Eigen::VectorXd& lambda, Prepared& out, int k, int bi, bool overflow,
                double* lp, double* other) {
  const int zero = out.body_entries;
  Batch& B = out.batches[static_cast<size_t>(bi)];
  int* row_of = out.row_of.data() + static_cast<size_t>(bi) * 2 * W;
  const int per = overflow ? 1 : W;
  const int s0 = out.start[static_cast<size_t>(k)] + (bi - out.batch_of[static_cast<size_t>(k)]) * per;
  const int lanes = std::min(per, out.start[static_cast<size_t>(k) + 1] - s0);
  double diag_n[W], diag_t[W];  // 1 for padding lanes and rows that failed to pack
  std::fill(diag_n, diag_n + W, 1.0);
  std::fill(diag_t, diag_t + W, 1.0);
  int& failed = out.failed[static_cast<size_t>(bi)];
  for (int lane = 0; lane < lanes; ++lane) {
    const int c = out.order[static_cast<size_t>(s0 + lane)];
    if (!pack_contact(p, out.dynamic, zero, c, B, lane, row_of, diag_n, diag_t) && failed < 0) failed = c;
  }
  pad(B, lanes, zero, row_of);
  const bool ok_n = scale_rows(B.jn, B.bn, diag_n), ok_t = scale_rows(B.jt, B.bt, diag_t);
  if ((!ok_n || !ok_t) && failed < 0) {  // name the first singular contact of the batch
    for (int lane = 0; lane < lanes && failed < 0; ++lane) {
      const double dn = diag_n[lane], dt = diag_t[lane];
      if (!(dn > 0 && std::isfinite(1.0 / dn)) || !(dt > 0 && std::isfinite(1.0 / dt)))
        failed = out.order[static_cast<size_t>(s0 + lane)];
    }
  }
  B.count = lanes;
  const size_t s0p = static_cast<size_t>(bi) * 2 * W;
  for (int s = 0; s < 2 * W; ++s) lp[s0p + s] = other[s0p + s] = row_of[s] >= 0 ? lambda[row_of[s]] : 0.0;
}

/// The first contact (in batch order) whose rows cannot be packed, as the reason "pgs" runs.
std::string first_failure(const Prepared& out) {
  for (const int c : out.failed)
    if (c >= 0) return "contact " + std::to_string(c) + "'s rows are singular or act on another body";
  return {};
}

/// True when no entry of x[0..n) is ±∞ or NaN: an OR over the exponent bits (integer ops, so
/// the compiler vectorises it).
bool all_finite(const double* x, int n) {
  constexpr std::uint64_t kExp = 0x7ff0000000000000ull;
  std::uint64_t any = 0;
  for (int i = 0; i < n; ++i) {
    std::uint64_t bits;
    std::memcpy(&bits, x + i, sizeof bits);
    any |= static_cast<std::uint64_t>((bits & kExp) == kExp);
  }
  return any == 0;
}

PgsColoredKernel resolve(PgsColoredKernel k) {
  if (k != PgsColoredKernel::Auto) {
    if (!pgs_colored_kernel_available(k))
      throw InvalidArgument(std::string("pgs-colored: the ") + to_string(k) + " kernel is not available on this CPU");
    return k;
  }
  return pgs_colored_auto_kernel();
}

colored::SweepKernel kernel_fn(PgsColoredKernel k) {
  switch (k) {
    case PgsColoredKernel::Avx512: return colored::sweep_avx512;
    case PgsColoredKernel::Avx2: return colored::sweep_avx2;
    default: return colored::sweep_scalar;
  }
}

/// Thread tid's share (of nt) of one sweep: each colour's batches split statically (contiguous
/// blocks, so a thread keeps the same region of the pile from colour to colour), the overflow
/// set on thread 0, a barrier after each colour. The thread's θ and flag go to `mine` before the
/// last barrier, so after it every thread's share is visible.
void sweep_share(const Prepared& prep, colored::SweepKernel sweep, const double* in, double* out, double* u, int tid,
                 int nt, colored::Acc& mine) {
  colored::Acc local;
  const Batch* batches = prep.batches.data();
  const int nr = static_cast<int>(prep.ranges.size());
  for (int k = 0; k < nr; ++k) {
    const Range& rg = prep.ranges[static_cast<size_t>(k)];
    if (rg.serial) {
      if (tid == 0) sweep(batches, rg.begin, rg.end, in, out, u, local);
    } else {
      const int n = rg.end - rg.begin;
      const int lo = rg.begin + static_cast<int>(static_cast<long>(n) * tid / nt);
      const int hi = rg.begin + static_cast<int>(static_cast<long>(n) * (tid + 1) / nt);
      sweep(batches, lo, hi, in, out, u, local);
    }
    if (k == nr - 1) mine = local;
#pragma omp barrier
  }
  if (nr == 0) mine = local;
}

/// What thread 0 (running the sweep driver) tells the others before each sweep.
struct SweepOrder {
  const double* in = nullptr;
  double* out = nullptr;
  bool stop = false;
};

class PgsColoredSolver final : public LcpSolver {
 public:
  explicit PgsColoredSolver(const PgsColoredDef& def)
      : def_(def), kernel_(kernel_fn(resolve(def.kernel))), colorer_(def.reuse_colors, def.color_chunk) {}
  [[nodiscard]] std::string name() const override { return "pgs-colored"; }
  [[nodiscard]] bool needs_jacobian() const override { return true; }
  [[nodiscard]] bool needs_assembled_matrix() const override { return false; }

  [[nodiscard]] SolveResult solve(const LcpProblem& p, const Eigen::VectorXd& lambda0,
                                  const SolverOptions& o) override {
    // λ⁰ as given (or zeros): the input checks run on the threads the packing will use.
    Eigen::VectorXd zeros;
    const Eigen::VectorXd* start = &lambda0;
    if (p.has_jacobian()) {
      const int threads = effective_threads(p.constraints.size() / W);
      if (auto bad = colored::check_input(p, lambda0, name(), threads, zeros, start)) return *bad;
    }
    const Eigen::VectorXd& lambda = *start;
    // The buffers of the last solve, taken out of the solver for this one: an exception drops
    // them, so the next solve lays out afresh instead of reusing a half-written layout.
    Prepared prep = std::exchange(cache_, Prepared{});
    std::string why = p.has_jacobian() ? std::string() : std::string("no Jacobian");
    if (why.empty()) why = layout(p, colorer_, effective_threads(p.constraints.size() / W), prep);
    // The permuted λ⁰ (both buffers: padding entries are never written by the scalar kernel).
    const int np = static_cast<int>(prep.row_of.size());
    Eigen::VectorXd lp(why.empty() ? np : 0), other(why.empty() ? np : 0);
    bool bad_start = false;
    if (why.empty()) why = pack(p, lambda, prep, lp.data(), other.data(), bad_start);
    if (!why.empty()) {
      SolveResult r = solvers::make_pgs_matrix_free()->solve(p, lambda0, o);
      if (r.status != SolveStatus::InvalidInput)
        r.message = "pgs-colored: " + why + ": ran pgs" + (r.message.empty() ? std::string() : "; " + r.message);
      cache_ = std::move(prep);
      return r;
    }
    SolveResult r = sweeps(p, std::move(lp), std::move(other), bad_start, o, prep);
    cache_ = std::move(prep);
    return r;
  }

 private:
  [[nodiscard]] int effective_threads(int batches) const {
#if defined(_OPENMP)
    int t = def_.threads > 0 ? def_.threads : omp_get_max_threads();
    if (t > 1 && batches < def_.min_batches_per_thread * t) t = 1;
    return std::max(1, t);
#else
    (void)batches;
    return 1;
#endif
  }

  /// Packs every batch, writes the permuted λ⁰ into lp and other, and computes Δu⁰ =
  /// M⁻¹Jᵀλ⁰Δt, in one parallel region: one thread takes Δu⁰ (a serial pass over J,
  /// pgs_colored_products.hpp) while the others start on the batches, which are handed out in
  /// chunks as threads come free. Each batch is written by one thread from its own inputs, so
  /// the result depends neither on the thread count nor on the schedule. bad_start: Δu⁰ is not
  /// finite (an overflowing λ⁰).
  [[nodiscard]] std::string pack(const LcpProblem& p, const Eigen::VectorXd& lambda, Prepared& prep, double* lp,
                                 double* other, bool& bad_start) const {
    const int nb = static_cast<int>(prep.batches.size());
    const int threads = effective_threads(nb);
    const int nk = static_cast<int>(prep.start.size()) - 1;  // colour slots, overflow last
    const int bodies = prep.body_entries / kStride;
    prep.du.resize(static_cast<size_t>(prep.body_entries + kStride));
    const int* first_batch = prep.batch_of.data();  // nk + 1 ascending offsets
    bool bad = false;
#pragma omp parallel num_threads(threads) if (threads > 1)
    {
#pragma omp single nowait
      {
        colored::velocity_change(p, lambda, bodies, prep.du.data(), prep.jt);
        bad = !all_finite(prep.du.data(), prep.body_entries);
      }
#pragma omp for schedule(dynamic, 16) nowait
      for (int bi = 0; bi < nb; ++bi) {
        const int k = static_cast<int>(std::upper_bound(first_batch, first_batch + nk + 1, bi) - first_batch) - 1;
        fill_batch(p, lambda, prep, k, bi, k == nk - 1, lp, other);
      }
    }
    bad_start = bad;
    return first_failure(prep);
  }

  /// The sweeps from the permuted λ⁰ (lp = other) on the packed problem; λ back in row order, its
  /// natural residual (bit-identical to finish's, pgs_colored_products.hpp). With threads, the
  /// permutation back and the residual's rows run on them too.
  [[nodiscard]] SolveResult sweeps(const LcpProblem& p, Eigen::VectorXd lp, Eigen::VectorXd other, bool bad_start,
                                   const SolverOptions& o, Prepared& prep) const {
    const int threads = effective_threads(static_cast<int>(prep.batches.size()));
    SolverOptions po = o;
    if (o.on_checkpoint)
      po.on_checkpoint = [&](int k, const Eigen::VectorXd& v) { o.on_checkpoint(k, unpermute(prep, v, p.rows(), threads)); };
    SolveResult r = threads <= 1 ? sweeps_serial(std::move(lp), std::move(other), bad_start, po, prep)
                                 : sweeps_threaded(std::move(lp), std::move(other), bad_start, po, prep, threads);
    r.lambda = unpermute(prep, r.lambda, p.rows(), threads);
    bool finite = false;
    r.residual = colored::natural_residual(p, r.lambda, threads, prep.jt, finite);
    if (finite)
      settle_status(p, r, o, StopRule::Tolerance);
    else
      finish(p, r, o, StopRule::Tolerance);  // the defensive replacement of a non-finite λ (and its residual)
    return r;
  }

  /// The sweeps on one thread.
  [[nodiscard]] SolveResult sweeps_serial(Eigen::VectorXd lp, Eigen::VectorXd other, bool bad_start,
                                          const SolverOptions& o, Prepared& prep) const {
    const colored::SweepKernel sweep = kernel_;
    return solvers::run_sweeps_double_buffered(
        std::move(lp), std::move(other), o, [&](const Eigen::VectorXd& in, Eigen::VectorXd& out, bool& nonfinite) {
          colored::Acc acc;
          acc.bad = bad_start;
          bad_start = false;
          for (const Range& rg : prep.ranges)
            sweep(prep.batches.data(), rg.begin, rg.end, in.data(), out.data(), prep.du.data(), acc);
          if (!std::isfinite(acc.theta)) acc.bad = true;
          nonfinite = nonfinite || acc.bad;
          return acc.theta;
        });
  }

  /// The sweeps on `threads` threads in one parallel region for the whole solve (no fork and
  /// join per sweep): thread 0 runs the sweep driver (checkpoints, tolerance, callbacks) and,
  /// per sweep, releases the others with a barrier; all take their share (sweep_share); θ and
  /// the flag are combined in thread order as max / or, so the result does not depend on the
  /// thread count. An exception of the driver (a callback) ends the region and is rethrown.
  [[nodiscard]] SolveResult sweeps_threaded(Eigen::VectorXd lp, Eigen::VectorXd other, bool bad_start,
                                            const SolverOptions& o, Prepared& prep, int threads) const {
    SolveResult r;
#if defined(_OPENMP)
    const colored::SweepKernel sweep = kernel_;
    SweepOrder order;
    std::vector<colored::Acc> share(static_cast<size_t>(threads));
    std::exception_ptr error;
#pragma omp parallel num_threads(threads)
    {
      const int tid = omp_get_thread_num(), nt = omp_get_num_threads();
      double* u = prep.du.data();
      if (tid == 0) {
        try {
          r = solvers::run_sweeps_double_buffered(
              std::move(lp), std::move(other), o,
              [&](const Eigen::VectorXd& in, Eigen::VectorXd& out, bool& nonfinite) {
                order.in = in.data();
                order.out = out.data();
#pragma omp barrier
                sweep_share(prep, sweep, order.in, order.out, u, 0, nt, share[0]);
                colored::Acc acc;
                acc.bad = bad_start;
                bad_start = false;
                for (int t = 0; t < nt; ++t) {
                  acc.theta = colored::max_of(acc.theta, share[static_cast<size_t>(t)].theta);
                  acc.bad = acc.bad || share[static_cast<size_t>(t)].bad;
                }
                if (!std::isfinite(acc.theta)) acc.bad = true;
                nonfinite = nonfinite || acc.bad;
                return acc.theta;
              });
        } catch (...) {
          error = std::current_exception();
        }
        order.stop = true;
#pragma omp barrier
      } else {
        for (;;) {
#pragma omp barrier
          if (order.stop) break;
          sweep_share(prep, sweep, order.in, order.out, u, tid, nt, share[static_cast<size_t>(tid)]);
        }
      }
    }
    if (error) std::rethrow_exception(error);
#else
    (void)threads;
    r = sweeps_serial(std::move(lp), std::move(other), bad_start, o, prep);
#endif
    return r;
  }

  /// λ in row order from the permuted vector v (every row has one slot: each row belongs to a
  /// packed contact).
  static Eigen::VectorXd unpermute(const Prepared& prep, const Eigen::VectorXd& v, int rows, int threads) {
    Eigen::VectorXd out(rows);
    const int np = static_cast<int>(prep.row_of.size());
#pragma omp parallel num_threads(threads) if (threads > 1)
    {
#pragma omp for schedule(static)
      for (int i = 0; i < rows; ++i) out[i] = 0.0;
#pragma omp for schedule(static)
      for (int s = 0; s < np; ++s)
        if (const int row = prep.row_of[static_cast<size_t>(s)]; row >= 0) out[row] = v[s];
    }
    return out;
  }

  PgsColoredDef def_;
  colored::SweepKernel kernel_;
  // The colouring of the last solve (reused where contacts persist) and its buffers: the
  // reason solve() is not const (one solver object per thread, lcp_solver.hpp).
  ContactColorer colorer_;
  Prepared cache_;
};

}  // namespace

std::unique_ptr<LcpSolver> make_pgs_colored(const PgsColoredDef& def) { return std::make_unique<PgsColoredSolver>(def); }

bool pgs_colored_kernel_available(PgsColoredKernel kernel) {
  switch (kernel) {
    case PgsColoredKernel::Avx512: return colored::cpu_has_avx512();
    case PgsColoredKernel::Avx2: return colored::cpu_has_avx2();
    default: return true;
  }
}

PgsColoredKernel pgs_colored_auto_kernel() {
  // AMD cores (Zen 4) execute 512-bit operations as two 256-bit halves: there the AVX2 kernel
  // is at least as fast (it also skips the all-padding half of a colour's last batch; micro_pgs,
  // docs/lcp.md "pgs-colored"). Elsewhere the AVX-512 kernel is preferred.
  if (colored::cpu_has_avx512() && !(colored::cpu_has_avx2() && colored::cpu_is_amd())) return PgsColoredKernel::Avx512;
  if (colored::cpu_has_avx2()) return PgsColoredKernel::Avx2;
  return PgsColoredKernel::Scalar;
}

const char* to_string(PgsColoredKernel kernel) {
  switch (kernel) {
    case PgsColoredKernel::Auto: return "auto";
    case PgsColoredKernel::Avx512: return "avx512";
    case PgsColoredKernel::Avx2: return "avx2";
    case PgsColoredKernel::Scalar: return "scalar";
  }
  return "?";
}

namespace solvers {
std::unique_ptr<LcpSolver> make_pgs_colored() { return dc::make_pgs_colored(PgsColoredDef{}); }
}  // namespace solvers

}  // namespace dc
