// "pgs-colored": colour-ordered matrix-free PGS, 8 contacts per lane group
// (dc/lcp/pgs_colored.hpp), after Box2D v3's graph-coloured solver, in double precision
// with "pgs"'s row form (J_i / A_ii pre-scaled, the same FMAs and tree sums) and its two-point
// manifold block. This file: the input checks, the packing run and the sweep driver; the
// set-up (colouring, manifold pairs, batches) is pgs_colored_layout.cpp, the kernels are
// pgs_colored_{scalar,avx2,avx512}.cpp (chosen in kernels/kernel_choice.cpp), the batch layout
// is pgs_colored_batch.hpp. λ lives in a
// permuted vector during the sweeps (pgs_colored_layout.hpp) and is mapped back at
// checkpoints and at the end. With threads each batch is written by one thread from its own
// inputs, so the result depends neither on the thread count nor on the schedule. A sweep does
// nothing but the kernel: λ^{k−1} and λ^k live in two buffers (run_sweeps_double_buffered)
// and the Δu finiteness check is fused into the kernels. Design: docs/lcp.md "`pgs-colored`".
// "nncg-colored" is the same solver with NNCG's momentum between the sweeps
// (MomentumBetweenSweeps, nncg_momentum.hpp; docs/solvers.md "nncg-colored").
#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <exception>
#include <limits>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include <time.h>

#if defined(_OPENMP)
#include <omp.h>
#endif

#include "dc/core/error.hpp"
#include "dc/core/work_team.hpp"
#include "dc/lcp/pgs_colored.hpp"
#include "solvers/pgs_colored/coloring/contact_coloring.hpp"
#include "solvers/pgs_colored/compact/compact_batch.hpp"
#include "solvers/pgs_colored/kernels/kernel_choice.hpp"
#include "solvers/pgs_colored/pgs_colored_batch.hpp"
#include "solvers/pgs_colored/pgs_colored_input.hpp"
#include "solvers/pgs_colored/pgs_colored_layout.hpp"
#include "solvers/pgs_colored/pgs_colored_products.hpp"
#include "solvers/pgs_colored/pgs_colored_residual.hpp"
#include "solvers/pgs_colored/relax/over_relaxation.hpp"
#include "solvers/pgs_colored/residual/packed_residual.hpp"
#include "solvers/pgs_colored/setup/team_pack.hpp"
#include "solvers/pgs_colored/sweep_plan.hpp"
#include "solvers/pgs_colored/sweep_team.hpp"
#include "solvers/pgs_colored/thread_pacer.hpp"
#include "solvers/nncg_momentum.hpp"
#include "solvers/solver_common.hpp"
#include "solvers/solvers.hpp"

namespace dc {
namespace {

using colored::Batch;
using colored::kernel_fn;
using colored::Kernels;
using colored::resolve;
using colored::run_range;
using colored::kStride;
using colored::Prepared;
using colored::Range;
using colored::W;
using solvers::finish;
using solvers::settle_status;
using solvers::StopRule;


/// Adds the thread CPU time since the last lap to a PgsColoredProfile field; does nothing
/// without a profile (no clock read).
class Laps {
 public:
  explicit Laps(PgsColoredProfile* p) : p_(p), t_(p != nullptr ? now() : 0.0) {}
  void lap(double PgsColoredProfile::*field) {
    if (p_ == nullptr) return;
    const double t = now();
    p_->*field += t - t_;
    t_ = t;
  }
  [[nodiscard]] PgsColoredProfile* profile() const { return p_; }

 private:
  static double now() {
    timespec ts{};
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
    return static_cast<double>(ts.tv_sec) + 1e-9 * static_cast<double>(ts.tv_nsec);
  }
  PgsColoredProfile* p_;
  double t_;
};

/// "pgs-colored", and "nncg-colored" (`nncg`): the same set-up and sweeps with NNCG's momentum
/// between them (nncg_momentum.hpp; `momentum` false: none, pgs-colored's iterates).
class PgsColoredSolver final : public LcpSolver {
 public:
  explicit PgsColoredSolver(const PgsColoredDef& def, bool nncg = false, bool momentum = false)
      : def_(def),
        kernel_(kernel_fn(resolve(def.kernel))),
        large_kernel_(def.kernel == PgsColoredKernel::Auto ? kernel_fn(pgs_colored_auto_kernel(colored::kLargeFrom))
                                                           : kernel_),
        colorer_(def.reuse_colors, def.color_chunk),
        nncg_(nncg), momentum_(nncg && momentum) {}
  [[nodiscard]] std::string name() const override { return nncg_ ? "nncg-colored" : "pgs-colored"; }
  [[nodiscard]] bool needs_jacobian() const override { return true; }
  [[nodiscard]] bool needs_assembled_matrix() const override { return false; }
  /// def_.threads (0: OpenMP's default) when forced (min_batches_per_thread = 0) or once the
  /// pacer has seen threaded solves pay (a free core: World::step then probes its stages on
  /// threads too), else 1.
  [[nodiscard]] int threads() const override {
#if defined(_OPENMP)
    const int t = std::max(1, def_.threads > 0 ? def_.threads : omp_get_max_threads());
    return def_.min_batches_per_thread == 0 || pacer_.proven() ? t : 1;
#else
    return 1;
#endif
  }
  /// def_.threads (0: OpenMP's default), paid or not.
  [[nodiscard]] int thread_capacity() const override {
#if defined(_OPENMP)
    return std::max(1, def_.threads > 0 ? def_.threads : omp_get_max_threads());
#else
    return 1;
#endif
  }
  /// (min_batches_per_thread = 0 threads every problem: no hold.)
  void hold_threads(bool serial) override { held_ = serial && def_.min_batches_per_thread > 0; }
  void lead_threads(bool led) override { led_ = led; }
  [[nodiscard]] bool threads_forced() const override { return def_.min_batches_per_thread == 0 && threads() > 1; }
  [[nodiscard]] ThreadPacer* step_pacer(double pays) override {
    if (!step_pacer_) step_pacer_.emplace(pays);
    return &*step_pacer_;
  }

  [[nodiscard]] SolveResult solve(const LcpProblem& p, const Eigen::VectorXd& lambda0,
                                  const SolverOptions& o) override {
    into_ = nullptr;
    return solve_paced(p, lambda0, o);
  }

  /// solve() with the caller's look every watch->every sweeps (solvers::nncg_colored_solve).
  [[nodiscard]] SolveResult solve_watched(const LcpProblem& p, const Eigen::VectorXd& lambda0, const SolverOptions& o,
                                          const solvers::SweepWatch* watch) {
    struct Reset {  // also after a throw
      const solvers::SweepWatch*& watch;
      ~Reset() { watch = nullptr; }
    } reset{watch_};
    watch_ = watch;
    into_ = nullptr;
    return solve_paced(p, lambda0, o);
  }

  /// λ of the packed path written straight into `lambda` (sweeps); every other path's copied.
  void solve_into(const LcpProblem& p, const Eigen::Ref<const Eigen::VectorXd>& lambda0, const SolverOptions& o,
                  KeptVector& lambda, SolveResult& result) override {
    struct Reset {  // also after a throw
      KeptVector*& into;
      ~Reset() { into = nullptr; }
    } reset{into_};
    into_ = &lambda;
    in_place_ = false;
    result = solve_paced(p, lambda0, o);
    if (!in_place_) lambda = result.lambda;
    result.lambda = Eigen::VectorXd();
  }

 private:
  /// solve(), with λ⁰ where it lies.
  [[nodiscard]] SolveResult solve_paced(const LcpProblem& p, const Eigen::Ref<const Eigen::VectorXd>& lambda0,
                                        const SolverOptions& o) {
    // Threads only while they pay (ThreadPacer), unless min_batches_per_thread = 0 forces them.
    if (!(o.omega > 0 && o.omega < 2)) return colored::invalid_omega(p, Eigen::VectorXd(lambda0), o);
    const bool paced = def_.threads != 1 && def_.min_batches_per_thread > 0 && !led_;
    serial_solve_ = held_ || (paced && !pacer_.threaded_next());
    serial_setup_ = paced && !pacer_.proven();
    solved_ = Solved{};
    const auto t0 = std::chrono::steady_clock::now();
    SolveResult r = solve_packed(p, lambda0, o);
    if (paced && solved_.batches > 0) {
      const std::chrono::duration<double> wall = std::chrono::steady_clock::now() - t0;
      pacer_.record(solved_.threads > 1, wall.count(), static_cast<double>(solved_.batches) * (r.sweeps + 2));
    }
    return r;
  }

  /// The solve itself: the checks, the layout and packing, the sweeps, or "pgs" for problems
  /// the kernels do not cover.
  [[nodiscard]] SolveResult solve_packed(const LcpProblem& p, const Eigen::Ref<const Eigen::VectorXd>& lambda0,
                                         const SolverOptions& o) {
    Laps laps(def_.profile);
    // λ⁰ as given (or zeros): the input checks run on the threads the packing will use.
    const double* start = lambda0.data();
    if (p.has_jacobian()) {
      const int threads = setup_threads(p.constraints.size() / W, expected_ranges());
      bool trusted = false;
      if (auto bad = colored::check_input(p, lambda0, name(), threads, zeros_, start, owner_, trusted)) return *bad;
      if (trusted && laps.profile() != nullptr) ++laps.profile()->structure_trusted;
    }
    laps.lap(&PgsColoredProfile::checks);
    const Eigen::Map<const Eigen::VectorXd> lambda(start, start == lambda0.data() ? lambda0.size() : p.rows());
    // The buffers of the last solve, taken out of the solver for this one: an exception drops
    // them, so the next solve lays out afresh instead of reusing a half-written layout.
    const size_t ranges_before = expected_ranges();
    Prepared prep = std::exchange(cache_, Prepared{});
    std::string why = p.has_jacobian() ? std::string() : std::string("no Jacobian");
    double* coloring_s = laps.profile() != nullptr ? &laps.profile()->coloring : nullptr;
    const double coloring_before = coloring_s != nullptr ? *coloring_s : 0.0;
    colored::OrderedColorer* ordered = def_.ordered_colors ? &ordered_ : nullptr;
    if (why.empty()) {
      // The locality order when the sweeps are expected on threads, on the pacer's probes too
      // (their set-up is serial): without it the threads' regions interleave over the pile and
      // a threaded probe could never pay; on one thread it costs more than it saves
      // (PgsColoredDef::locality_order).
      const long batches = p.constraints.size() / W;
      const int threads = setup_threads(batches, ranges_before);
      const bool local = def_.locality_order && effective_threads(batches, ranges_before) > 1;
      why = colored::layout(p, colorer_, ordered, threads, prep, coloring_s, local);
    }
    laps.lap(&PgsColoredProfile::ordering);  // the layout, less its colouring:
    if (coloring_s != nullptr) laps.profile()->ordering -= *coloring_s - coloring_before;
    // The permuted λ⁰ (both buffers: padding entries are never written by the scalar kernel),
    // in the storage of the last solve's: at least np entries (only the first np are used), so
    // a solve allocates them only when the problem outgrows every earlier one.
    const int np = static_cast<int>(prep.row_of.size());
    Eigen::VectorXd lp = std::move(prep.lp), other = std::move(prep.other);
    if (why.empty()) {
      keep_at_least(lp, np);
      keep_at_least(other, np);
    }
    bool bad_start = false;
    if (why.empty()) why = pack(p, lambda, o.omega, prep, lp.data(), other.data(), bad_start, laps);
    if (!why.empty()) {
      // nncg-colored: "nncg" (with the caller's watch), the same method on pgs's sweep.
      SolveResult r = momentum_ ? solvers::nncg_solve(p, Eigen::VectorXd(lambda0), o, watch_)
                                : solvers::make_pgs_matrix_free()->solve(p, Eigen::VectorXd(lambda0), o);
      if (r.status != SolveStatus::InvalidInput)
        r.message = name() + ": " + why + (momentum_ ? ": ran nncg" : ": ran pgs") +
                    (r.message.empty() ? std::string() : "; " + r.message);
      prep.lp = std::move(lp);
      prep.other = std::move(other);
      cache_ = std::move(prep);
      return r;
    }
    SolveResult r = sweeps(p, std::move(lp), std::move(other), bad_start, o, prep, laps);
    if (laps.profile() != nullptr) ++laps.profile()->solves;
    cache_ = std::move(prep);
    return r;
  }

  /// v with at least n entries (their values undefined): reallocated, with an eighth more room,
  /// only when it has fewer (an Eigen vector reallocates on every change of size).
  static void keep_at_least(Eigen::VectorXd& v, int n) {
    if (v.size() < n) v.resize(n + n / 8);
  }

  /// Threads for `batches` batches in `ranges` colour ranges (threads_for): def_.threads (0:
  /// OpenMP's default), or 1 for a small problem or when the pacer chose a serial solve.
  [[nodiscard]] int effective_threads(long batches, size_t ranges) const {
#if defined(_OPENMP)
    if (serial_solve_) return 1;
    const int t = std::max(1, def_.threads > 0 ? def_.threads : omp_get_max_threads());
    return colored::threads_for(t, def_.min_batches_per_thread, batches, ranges);
#else
    (void)batches;
    (void)ranges;
    return 1;
#endif
  }

  /// Threads for the set-up's parallel regions (checks, layout, packing, the permutation back,
  /// the residual): effective_threads, or 1 while the pacer has not seen threaded solves pay.
  [[nodiscard]] int setup_threads(long batches, size_t ranges) const {
    return serial_setup_ ? 1 : effective_threads(batches, ranges);
  }

  /// The colour ranges a solve is expected to sweep before its layout: the last solve's, else
  /// kNominalRanges.
  [[nodiscard]] size_t expected_ranges() const {
    return cache_.ranges.empty() ? kNominalRanges : cache_.ranges.size();
  }
  static constexpr size_t kNominalRanges = 8;

  /// Packs every batch, writes the permuted λ⁰ into lp and other, and computes Δu⁰ =
  /// M⁻¹Jᵀλ⁰Δt on the team (setup/team_pack.hpp): one run in which one thread takes Δu⁰ (a
  /// serial pass over J, pgs_colored_products.hpp) while the others start on their blocks of
  /// each colour's batches, handed out in parts as threads come free. Each batch is written by one thread from its own inputs, so the result
  /// depends neither on the thread count nor on the schedule. Each batch is
  /// over-relaxed by ω as it is filled (relax/over_relaxation.hpp). bad_start: Δu⁰ is not
  /// finite (an overflowing λ⁰). Δu⁰ leaves out the test that J is finite, which its skip of
  /// the rows with λ_i = 0 needs: a packing that succeeds has verified it (every row's A_ii
  /// finite, scale_rows), one that fails sends the solve to "pgs" without Δu⁰.
  [[nodiscard]] std::string pack(const LcpProblem& p, const Eigen::Ref<const Eigen::VectorXd>& lambda, double omega,
                                 Prepared& prep,
                                 double* lp,
                                 double* other, bool& bad_start, Laps& laps) const {
    const int nb = static_cast<int>(prep.batches.size());
    const int jobs = nb + static_cast<int>(prep.pairs.size());  // batches, then pair batches
    const int threads = setup_threads(jobs, prep.ranges.size());
    const int bodies = prep.body_entries / kStride;
    prep.du.resize(static_cast<size_t>(prep.body_entries + kStride));
    bool bad = false;
    auto delta_u0 = [&](int) {
      bool unchecked = false;
      bad = !colored::velocity_change_checked(p, lambda, bodies, prep.du.data(), prep.jt, unchecked,
                                              prep.numbering.slot.data(), false);
    };
    // This solve's kernels (kernels_of: Auto's for the size), then the compact layout
    // (PgsColoredDef::compact_layout) when every batch compresses exactly.
    prep.wide_pack = (nb >= colored::kLargeFrom ? large_kernel_ : kernel_).single == colored::sweep_avx512;
    const int from = def_.compact_from_batches >= 0 ? def_.compact_from_batches
                     : prep.wide_pack                ? colored::kLargeFrom
                                                     : std::numeric_limits<int>::max();
    const bool compact = def_.compact_layout && nb > 0 && nb >= from;
    if (threads <= 1) {
      delta_u0(0);
      laps.lap(&PgsColoredProfile::du0);
      colored::pack_batches(p, lambda, omega, compact, prep, lp, other, 1);
    } else {
      // Δu⁰ as one more part of the pack's run (setup/team_pack.hpp); the sources gathered from J
      // in colour order, not staged: when a helper is kept off its core, member 0 alone would
      // pay the staging pass on top of the pack (step_threads --min-batches 0 --profile).
      const PartJob side(delta_u0);
      colored::pack_batches(p, lambda, omega, compact, prep, lp, other, threads, &side, std::numeric_limits<int>::max());
    }
    bad_start = bad;
    if (laps.profile() != nullptr) {
      if (prep.compact_on) ++laps.profile()->compact_solves;
      const std::size_t batch = prep.compact_on ? sizeof(colored::CompactBatch) : sizeof(colored::Batch);
      laps.profile()->sweep_bytes = static_cast<long>(
          static_cast<std::size_t>(nb) * batch + prep.pairs.size() * sizeof(colored::PairBatch) +
          (prep.du.size() + 2 * prep.row_of.size()) * sizeof(double));
    }
    std::string failure = colored::first_failure(prep);
    prep.j_finite = failure.empty();
    laps.lap(&PgsColoredProfile::pack);
    return failure;
  }

  /// The sweeps from the permuted λ⁰ (lp = other) on the packed problem; λ back in row order, its
  /// natural residual: on the packed rows from the Δu the sweeps maintain when that Δu belongs to
  /// λ (residual/packed_residual.hpp), else (a non-finite value on the way, a non-finite J entry)
  /// by the products with J (bit-identical to finish's, pgs_colored_products.hpp). With threads,
  /// the permutation back and the residual run on them too.
  [[nodiscard]] SolveResult sweeps(const LcpProblem& p, Eigen::VectorXd lp, Eigen::VectorXd other, bool bad_start,
                                   const SolverOptions& o, Prepared& prep, Laps& laps) {
    const long batches = static_cast<long>(prep.batches.size() + prep.pairs.size());
    const int threads = o.symmetric ? 1 : effective_threads(batches, prep.ranges.size());
    const int setup = serial_setup_ ? 1 : threads;  // the permutation back and the residual
    solved_ = Solved{batches, threads};
    SolverOptions po = o;
    // λ in row order for the checkpoints and the watch (as often as every sweep): a branch-free
    // gather through each row's slot (row_of inverted once per solve; row_of's scan tests padding).
    Eigen::VectorXd& seen = seen_;
    if (o.on_checkpoint || watch_ != nullptr) {
      seen.resize(p.rows());
      slot_of_row_.assign(static_cast<size_t>(p.rows()), 0);
      for (size_t s = 0; s < prep.row_of.size(); ++s)
        if (prep.row_of[s] >= 0) slot_of_row_[static_cast<size_t>(prep.row_of[s])] = static_cast<int>(s);
    }
    const auto look = [&](const Eigen::VectorXd& v) {
      for (int r = 0; r < seen.size(); ++r) seen[r] = v[slot_of_row_[static_cast<size_t>(r)]];
    };
    if (o.on_checkpoint)
      po.on_checkpoint = [&](int k, const Eigen::VectorXd& v) {
        look(v);
        o.on_checkpoint(k, seen);
      };
    const bool start_bad = bad_start;
    // nncg-colored: the momentum on the packed λ (padding slots stay 0: p and the start of
    // their first sweep are 0, and no kernel moves a padding lane off 0) and on all of Δu (the
    // zero body and each body's padding entry never change, so their p stays 0).
    std::optional<solvers::NncgMomentum> momentum;
    if (momentum_) momentum.emplace(static_cast<int>(prep.row_of.size()), static_cast<int>(prep.du.size()));
    solvers::SweepWatch watch;  // the caller's, with λ back in row order
    if (watch_ != nullptr) {
      watch.every = watch_->every;
      watch.stop = [&](int k, const Eigen::VectorXd& v) {
        look(v);
        return watch_->stop(k, seen);
      };
    }
    const solvers::MomentumBetweenSweeps between{momentum ? &*momentum : nullptr, watch_ != nullptr ? &watch : nullptr};
    SolveResult r = threads <= 1 ? sweeps_serial(std::move(lp), std::move(other), bad_start, po, prep, plan_, between)
                                 : sweeps_threaded(std::move(lp), std::move(other), bad_start, po, prep, threads, between);
    if (momentum)
      r.message += (r.message.empty() ? "" : "; ") + std::to_string(momentum->restarts()) + " restart(s) of the CG direction";
    laps.lap(&PgsColoredProfile::sweeps);
    Eigen::VectorXd permuted = std::move(r.lambda);
    const bool packed = prep.j_finite && !start_bad && r.status != SolveStatus::Diverged;
    if (packed) {  // λ back in row order by the residual's chunks (every entry written), in place for solve_into
      double* out = nullptr;
      if (into_ != nullptr) {
        into_->resize(p.rows());
        out = into_->data();
      } else {
        r.lambda.resize(p.rows());
        out = r.lambda.data();
      }
      const colored::ResidualAcc e = colored::packed_residual(prep, permuted.data(), o.omega, kernels_of(prep).residual, setup, out);
      prep.lp = std::move(permuted);     // storage for the next solve's λ⁰
      if (!e.nan && std::isfinite(e.r)) {  // (a non-finite λ_i has a NaN or infinite error)
        r.residual = e.r;
        settle_status(p, r, o, StopRule::Tolerance);
        in_place_ = into_ != nullptr;
        laps.lap(&PgsColoredProfile::residual);
        return r;
      }
      if (into_ != nullptr) r.lambda = Eigen::VectorXd(*into_);  // (the checked path below reads r.lambda)
    } else {
      r.lambda = unpermute(prep, permuted, p.rows(), setup);
      prep.lp = std::move(permuted);
      laps.lap(&PgsColoredProfile::unpermute);
    }
    bool finite = false;
    r.residual = colored::natural_residual(p, r.lambda, setup, prep.jt, finite, prep.j_finite);
    if (finite)
      settle_status(p, r, o, StopRule::Tolerance);
    else
      finish(p, r, o, StopRule::Tolerance);  // the defensive replacement of a non-finite λ (and its residual)
    laps.lap(&PgsColoredProfile::residual);
    return r;
  }

  /// The sweeps on one thread, by the plan of prep's ranges (sweep_plan.hpp: tiny colours on
  /// the scalar kernel, the same bits).
  [[nodiscard]] SolveResult sweeps_serial(Eigen::VectorXd lp, Eigen::VectorXd other, bool bad_start,
                                          const SolverOptions& o, Prepared& prep,
                                          std::vector<colored::SweepStep>& plan, const solvers::MomentumBetweenSweeps& between) const {
    const Kernels sweep = kernels_of(prep), scalar = kernel_fn(PgsColoredKernel::Scalar);
    colored::plan_sweep(prep, colored::kScalarLanes, plan);
    long sweep_index = 0;
    return solvers::run_sweeps_double_buffered(
        std::move(lp), std::move(other), o, [&](const Eigen::VectorXd& last, Eigen::VectorXd& out, bool& nonfinite) {
          const double* in = between.start(last.data(), prep.du.data());
          colored::Acc acc;
          acc.bad = bad_start;
          bad_start = false;
          if (o.symmetric && (sweep_index++ & 1) != 0) {
            // The colour ranges last to first (SolverOptions::symmetric), each its own call: a
            // plan step may join several small colours. (A colour's batches touch disjoint
            // bodies: their order within it changes nothing.)
            for (auto rg = prep.ranges.rbegin(); rg != prep.ranges.rend(); ++rg)
              run_range(prep, sweep, *rg, rg->begin, rg->end, in, out.data(), prep.du.data(), acc);
          } else {
            for (const colored::SweepStep& st : plan)
              run_range(prep, st.scalar ? scalar : sweep, Range{st.begin, st.end, false, st.pairs}, st.begin, st.end,
                        in, out.data(), prep.du.data(), acc);
          }
          acc.bad = acc.bad || !between.finish(out.data(), acc.theta);
          nonfinite = nonfinite || acc.bad;
          return acc.theta;
        },
        &prep.other, between.watch);
  }

  /// The sweeps on `threads` members of the calling thread's team (dc/core/work_team.hpp) in
  /// one run for the whole solve (no fork and join per sweep): member 0 runs the sweep driver (checkpoints, tolerance, callbacks) and
  /// publishes each sweep; every thread takes chunks of each colour's batches (SweepTeam, which
  /// lets the present threads do the share of a descheduled one); θ and the flag are combined as
  /// max / or, so the result does not depend on the thread count or the schedule. An exception of
  /// the driver (a callback) stops the helpers and is rethrown.
  [[nodiscard]] SolveResult sweeps_threaded(Eigen::VectorXd lp, Eigen::VectorXd other, bool bad_start,
                                            const SolverOptions& o, Prepared& prep, int threads,
                                            const solvers::MomentumBetweenSweeps& between) {
    SolveResult r;
    const Kernels sweep = kernels_of(prep);
    colored::region_cuts(prep, threads, region_keys_, region_cuts_);  // each thread's region of the bodies
    team_.reset(prep.ranges, threads, region_cuts_);
    colored::SweepTeam& team = team_;
    double* u = prep.du.data();
    calling_thread_team().gather(threads, [&](int tid) {
      const double* in = nullptr;
      double* out = nullptr;
      auto run = [&](int k, int lo, int hi, colored::Acc& acc) {
        run_range(prep, sweep, prep.ranges[static_cast<size_t>(k)], lo, hi, in, out, u, acc);
      };
      if (tid != 0) {
        int s = -1;
        for (int last = -1; team.next(last, s, in, out); last = s) team.share(s, tid, run);
        return;
      }
      struct Stop {  // after the driver, also after a throw: the helpers return
        colored::SweepTeam& team;
        ~Stop() { team.stop(); }
      } stop{team};
      int s = 0;
      r = solvers::run_sweeps_double_buffered(
          std::move(lp), std::move(other), o,
          [&](const Eigen::VectorXd& vin, Eigen::VectorXd& vout, bool& nonfinite) {
            in = between.start(vin.data(), u);  // (the helpers wait for team.start)
            out = vout.data();
            team.start(s, in, out);
            team.share(s, 0, run);
            colored::Acc acc = team.finish(s++);
            acc.bad = acc.bad || bad_start;
            bad_start = false;
            acc.bad = acc.bad || !between.finish(vout.data(), acc.theta);
            nonfinite = nonfinite || acc.bad;
            return acc.theta;
          },
          &prep.other, between.watch);
    });
    return r;
  }

  /// λ in row order from the permuted vector v (every row has one slot: each row belongs to a
  /// packed contact).
  static Eigen::VectorXd unpermute(const Prepared& prep, const Eigen::VectorXd& v, int rows, int threads) {
    Eigen::VectorXd out(rows);  // (every entry is written below)
    const int np = static_cast<int>(prep.row_of.size());
    const int parts = threads > 1 ? 2 * threads : 1;
    calling_thread_team().for_parts(threads, parts, [&](int part) {
      const int end = static_cast<int>(part_begin(np, parts, part + 1));
      for (int s = static_cast<int>(part_begin(np, parts, part)); s < end; ++s)
        if (const int row = prep.row_of[static_cast<size_t>(s)]; row >= 0) out[row] = v[s];
    });
    return out;
  }

  /// The kernels of a solve packed by pack(): the AVX-512 ones exactly when it packed for them.
  [[nodiscard]] const Kernels& kernels_of(const Prepared& prep) const {
    return prep.wide_pack ? large_kernel_ : kernel_;
  }

  PgsColoredDef def_;
  Kernels kernel_;        // the chosen kernel (Auto: for problems below kLargeFrom batches)
  Kernels large_kernel_;  // Auto's for kLargeFrom batches and more; else kernel_
  // The colouring of the last solve (reused where contacts persist) and its buffers: the
  // reason solve() is not const (one solver object per thread, lcp_solver.hpp).
  ContactColorer colorer_;
  colored::OrderedColorer ordered_;
  Prepared cache_;
  std::vector<colored::SweepStep> plan_;  // the serial sweep's kernel calls (storage reused)
  std::vector<int> owner_;  // scratch of the input checks
  // The threaded sweeps' team and its regions (region_cuts), kept from solve to solve.
  colored::SweepTeam team_;
  std::vector<int> region_keys_, region_cuts_;
  KeptVector* into_ = nullptr;  // solve_into's λ, during its solve
  Eigen::VectorXd seen_;        // λ in row order for the checkpoints and the watch (storage kept)
  std::vector<int> slot_of_row_;  // the slot of each row (the looks' gather; storage kept)
  bool nncg_ = false;           // "nncg-colored"
  bool momentum_ = false;       // nncg-colored with its momentum (NncgColoredDef::momentum)
  const solvers::SweepWatch* watch_ = nullptr;  // solve_watched's, during its solve
  bool in_place_ = false;       // the solve wrote λ into *into_
  Eigen::VectorXd zeros_;   // λ⁰ when the caller passes none
  /// What the last solve swept: its batches (0: it ran "pgs" instead) and its sweeps' threads.
  struct Solved {
    long batches = 0;
    int threads = 1;
  };
  Solved solved_;
  colored::ThreadPacer pacer_;
  std::optional<ThreadPacer> step_pacer_;  // the pacer of the steps that lead this solver (step_pacer)
  bool serial_solve_ = false;  // this solve runs on one thread (the pacer's choice)
  bool serial_setup_ = false;  // this solve's set-up runs on one thread (a probe, or serial)
  bool held_ = false;          // hold_threads(true): every solve serial
  bool led_ = false;           // lead_threads(true): the caller paces (no pacing here)
};

}  // namespace

std::unique_ptr<LcpSolver> make_pgs_colored(const PgsColoredDef& def) { return std::make_unique<PgsColoredSolver>(def); }

std::unique_ptr<LcpSolver> make_nncg_colored(const NncgColoredDef& def) {
  // Contact order in the packed λ on any thread count: β's sums run in that order.
  PgsColoredDef sweep = def.sweep;
  if (def.momentum) sweep.locality_order = false;
  return std::make_unique<PgsColoredSolver>(sweep, true, def.momentum);
}

namespace solvers {
std::unique_ptr<LcpSolver> make_pgs_colored() { return dc::make_pgs_colored(PgsColoredDef{}); }

SolveResult nncg_colored_solve(LcpSolver& solver, const LcpProblem& p, const Eigen::VectorXd& lambda0,
                               const SolverOptions& o, const SweepWatch* watch) {
  auto* colored = dynamic_cast<PgsColoredSolver*>(&solver);
  if (colored == nullptr || solver.name() != "nncg-colored")
    throw InvalidArgument("nncg_colored_solve: the solver is not make_nncg_colored's");
  return colored->solve_watched(p, lambda0, o, watch);
}
}  // namespace solvers

}  // namespace dc
