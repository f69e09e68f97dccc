// "pgs-colored": colour-ordered matrix-free PGS, 8 contacts per lane group
// (dc/lcp/pgs_colored.hpp), after Box2D v3's graph-coloured solver, in double precision
// with "pgs"'s row form (J_i / A_ii pre-scaled, the same FMAs and tree sums) and its two-point
// manifold block. This file: the input checks, the packing run and the sweep driver; the
// set-up (colouring, manifold pairs, batches) is pgs_colored_layout.cpp, the kernels are
// pgs_colored_{scalar,avx2,avx512}.cpp, the batch layout is pgs_colored_batch.hpp. λ lives in a
// permuted vector during the sweeps (pgs_colored_layout.hpp) and is mapped back at
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
#include "solvers/pgs_colored/pgs_colored_layout.hpp"
#include "solvers/pgs_colored/pgs_colored_products.hpp"
#include "solvers/solver_common.hpp"
#include "solvers/solvers.hpp"

namespace dc {
namespace {

using colored::Batch;
using colored::kStride;
using colored::Prepared;
using colored::Range;
using colored::W;
using solvers::finish;
using solvers::settle_status;
using solvers::StopRule;


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

/// The kernels of one ISA: single-contact batches and two-point manifold batches.
struct Kernels {
  colored::SweepKernel single;
  colored::PairKernel pairs;
};

Kernels kernel_fn(PgsColoredKernel k) {
  switch (k) {
    case PgsColoredKernel::Avx512: return {colored::sweep_avx512, colored::sweep_pairs_avx512};
    case PgsColoredKernel::Avx2: return {colored::sweep_avx2, colored::sweep_pairs_avx2};
    default: return {colored::sweep_scalar, colored::sweep_pairs_scalar};
  }
}

/// Batches [lo, hi) of range rg with the kernel of its kind (pair batches' λ from pair_base).
inline void run_range(const Prepared& prep, const Kernels& kern, const Range& rg, int lo, int hi, const double* in,
                      double* out, double* u, colored::Acc& acc) {
  if (rg.pairs)
    kern.pairs(prep.pairs.data(), lo, hi, in + prep.pair_base, out + prep.pair_base, u, acc);
  else
    kern.single(prep.batches.data(), lo, hi, in, out, u, acc);
}

/// Thread tid's share (of nt) of one sweep: each colour's batches split statically (contiguous
/// blocks, so a thread keeps the same region of the pile from colour to colour), the overflow
/// set on thread 0, a barrier after each colour. The thread's θ and flag go to `mine` before the
/// last barrier, so after it every thread's share is visible.
void sweep_share(const Prepared& prep, const Kernels& sweep, const double* in, double* out, double* u, int tid,
                 int nt, colored::Acc& mine) {
  colored::Acc local;
  const int nr = static_cast<int>(prep.ranges.size());
  for (int k = 0; k < nr; ++k) {
    const Range& rg = prep.ranges[static_cast<size_t>(k)];
    if (rg.serial) {
      if (tid == 0) run_range(prep, sweep, rg, rg.begin, rg.end, in, out, u, local);
    } else {
      const int n = rg.end - rg.begin;
      const int lo = rg.begin + static_cast<int>(static_cast<long>(n) * tid / nt);
      const int hi = rg.begin + static_cast<int>(static_cast<long>(n) * (tid + 1) / nt);
      run_range(prep, sweep, rg, lo, hi, in, out, u, local);
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
      if (auto bad = colored::check_input(p, lambda0, name(), threads, zeros, start, owner_)) return *bad;
    }
    const Eigen::VectorXd& lambda = *start;
    // The buffers of the last solve, taken out of the solver for this one: an exception drops
    // them, so the next solve lays out afresh instead of reusing a half-written layout.
    Prepared prep = std::exchange(cache_, Prepared{});
    std::string why = p.has_jacobian() ? std::string() : std::string("no Jacobian");
    colored::OrderedColorer* ordered = def_.ordered_colors ? &ordered_ : nullptr;
    if (why.empty()) why = colored::layout(p, colorer_, ordered, effective_threads(p.constraints.size() / W), prep);
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
    const int jobs = nb + static_cast<int>(prep.pairs.size());  // batches, then pair batches
    const int threads = effective_threads(jobs);
    const int bodies = prep.body_entries / kStride;
    prep.du.resize(static_cast<size_t>(prep.body_entries + kStride));
    bool bad = false;
#pragma omp parallel num_threads(threads) if (threads > 1)
    {
#pragma omp single nowait
      {
        colored::velocity_change(p, lambda, bodies, prep.du.data(), prep.jt);
        bad = !all_finite(prep.du.data(), prep.body_entries);
      }
#pragma omp for schedule(dynamic, 16) nowait
      for (int bi = 0; bi < jobs; ++bi) {
        if (bi < nb)
          colored::fill_batch(p, lambda, prep, bi, lp, other);
        else
          colored::fill_pair(p, lambda, prep, bi - nb, lp, other);
      }
    }
    bad_start = bad;
    return colored::first_failure(prep);
  }

  /// The sweeps from the permuted λ⁰ (lp = other) on the packed problem; λ back in row order, its
  /// natural residual (bit-identical to finish's, pgs_colored_products.hpp). With threads, the
  /// permutation back and the residual's rows run on them too.
  [[nodiscard]] SolveResult sweeps(const LcpProblem& p, Eigen::VectorXd lp, Eigen::VectorXd other, bool bad_start,
                                   const SolverOptions& o, Prepared& prep) const {
    const int threads = effective_threads(static_cast<int>(prep.batches.size() + prep.pairs.size()));
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
    const Kernels sweep = kernel_;
    return solvers::run_sweeps_double_buffered(
        std::move(lp), std::move(other), o, [&](const Eigen::VectorXd& in, Eigen::VectorXd& out, bool& nonfinite) {
          colored::Acc acc;
          acc.bad = bad_start;
          bad_start = false;
          for (const Range& rg : prep.ranges)
            run_range(prep, sweep, rg, rg.begin, rg.end, in.data(), out.data(), prep.du.data(), acc);
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
    const Kernels sweep = kernel_;
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
  Kernels kernel_;
  // The colouring of the last solve (reused where contacts persist) and its buffers: the
  // reason solve() is not const (one solver object per thread, lcp_solver.hpp).
  ContactColorer colorer_;
  colored::OrderedColorer ordered_;
  Prepared cache_;
  std::vector<int> owner_;  // scratch of the input checks
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
