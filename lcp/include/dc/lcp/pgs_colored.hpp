#pragma once
// "pgs-colored": matrix-free projected Gauss–Seidel in colour order (docs/design.md §8.4,
// docs/lcp.md "`pgs-colored`"). The contacts are coloured (by default in contact order,
// ordered_coloring.hpp) and a sweep solves colour 0, 1, …, then the overflow set; 8 contacts of a
// colour are solved at once in SIMD lanes (normal + tangent row as in "pgs") and a colour's
// batches can run on threads (dc/core/work_team.hpp). Kernels AVX-512, AVX2 and scalar, chosen at run time
// (PgsColoredKernel::Auto). Same fixed points as "pgs"; with the ordered colouring also its
// iterates while the contact chains fit in 64 colours. The lane arithmetic is the scalar kernel's operation for
// operation, so every kernel and thread count gives bit-identical iterates. The solver object
// keeps last solve's colours (reused where contacts persist): solves are deterministic for a
// fixed sequence of problems. Problems the kernels do not cover (no contact constraints,
// singular rows, other bounds) are solved by "pgs", and the result's message says so.
#include <memory>

#include "dc/lcp/lcp_solver.hpp"

namespace dc {

// PgsColoredKernel, the sweep kernel, is declared in lcp_solver.hpp (SolverId names it).

/// Thread CPU seconds of the parts of pgs-colored's solves, summed over the solves that ran the
/// colour-ordered sweeps (timing only: nothing a solve computes depends on it). The parts run
/// in this order; `pack` excludes `du0`, which overlaps it when there are threads (then the
/// figures are the calling thread's only).
struct PgsColoredProfile {
  double checks = 0;     ///< the input checks (LcpProblem::validate and λ⁰)
  double coloring = 0;   ///< ContactColorer::color
  double ordering = 0;   ///< the rest of the layout: manifold pairs, counting sort into batches
  double pack = 0;       ///< filling the batches and the permuted λ⁰
  double du0 = 0;        ///< Δu⁰ = M⁻¹Jᵀλ⁰Δt
  double sweeps = 0;     ///< the sweeps
  double unpermute = 0;  ///< λ back in row order (a pass of its own only when the residual is formed from J)
  double residual = 0;   ///< the natural residual and the status (on the packed rows: with λ back in row order)
  long solves = 0;
  /// Solves whose structural checks were skipped: the problem's StructureStamp held (built
  /// valid by construction), so only b, λ⁰ and A were checked finite.
  long structure_trusted = 0;
  /// Solves whose single-contact batches were swept in the compact layout
  /// (PgsColoredDef::compact_layout).
  long compact_solves = 0;
  /// The bytes one sweep of the last solve streams: its packed batches (in the compact layout
  /// when it was used), pair batches, the bodies' Δu and the two permuted λ buffers. Compare with
  /// the core's caches to see whether the sweeps run from cache or from memory (docs/engine.md).
  long sweep_bytes = 0;
};

struct PgsColoredDef {
  /// Threads for the set-up and the batches of a colour (1 = serial; 0 = OpenMP's
  /// default). A problem runs on one thread unless its colour ranges (each a wait between the
  /// threads per sweep) average at least `min_batches_per_thread`·threads batches of 8
  /// contacts; 0 threads every problem. The threads' waits spin briefly, then yield, then sleep,
  /// and a descheduled thread's share of a colour is taken by the others (docs/lcp.md
  /// "pgs-colored", Threads).
  int threads = 1;
  /// Default 16: a wait between two spinning threads costs about as much as a few batches'
  /// sweep with the AVX-512 kernel, so a thread's share of a range of 16 batches keeps the
  /// waits a small part of the sweep; ordered colours give a settled pile many short ranges
  /// (a range a colour), and piles that gain from two threads have few batches per range.
  int min_batches_per_thread = 16;
  /// Which kernel sweeps (default Auto: chosen per solve by the CPU and the problem's size,
  /// pgs_colored_auto_kernel; every kernel gives the same bits). make_pgs_colored throws
  /// InvalidArgument for a kernel this build or CPU cannot run (pgs_colored_kernel_available).
  PgsColoredKernel kernel = PgsColoredKernel::Auto;
  /// Colour in contact order (true, the default): each contact takes the colour after those of
  /// its bodies' earlier contacts, so the sweep visits every two contacts that share a body in
  /// "pgs"'s order and gives its iterates while the chains fit in 64 colours (docs/lcp.md
  /// "Colour order"). false: the greedy colouring (the lowest free colour; reuse_colors and
  /// color_chunk apply only to it), fewer colours but a red–black order on stacks.
  bool ordered_colors = true;
  /// Greedy colouring: reuse last solve's colours where contacts persist (false: from scratch).
  bool reuse_colors = true;
  /// Contacts per chunk of the parallel colouring (docs/lcp.md "Contact colouring: repeats and
  /// chunks"; ContactColorer::kChunk is the benchmarked choice): a function of the contact
  /// count only, so the colours do not depend on `threads`. Problems with fewer than
  /// 2·color_chunk contacts are coloured as one chunk. 0 (the default) = the serial greedy
  /// colouring always: the chunked one needs one colour more on large piles, which costs the
  /// 2-thread sweeps more than the parallel colouring saves (docs/lcp.md "pgs-colored",
  /// "Alternatives considered").
  int color_chunk = 0;
  /// When a solve's sweeps run on threads (its set-up on threads, or serial on the pacer's
  /// probes): store the bodies' Δu in a locality order during the
  /// sweeps (true, the default): numbered breadth-first on the contact graph, each colour's
  /// contacts in that order, so each thread's region of the bodies (the sweeps' split) is one
  /// compact piece of the pile and few Δu cache lines move between the cores (docs/lcp.md
  /// "pgs-colored", Threads). The same result bits either way; false, and on one thread (where
  /// the numbering and the scattered packing cost more than the sweeps gain): each colour in
  /// contact order.
  bool locality_order = true;
  /// Sweep the single-contact batches in the compact layout (true, the default): without the
  /// coefficients that follow bit for bit from the others (body b's linear J entries, the
  /// tangent's M⁻¹JᵀΔt entries turned from the normal's), so the sweeps stream fewer bytes. The
  /// pack checks every batch bit for bit and keeps the full layout for a problem where one does
  /// not compress exactly (a general or non-isotropic M⁻¹, rows not of the engine's form): the
  /// same iterates either way. false: the full layout always.
  bool compact_layout = true;
  /// The compact layout only for solves with at least this many single-contact batches (0:
  /// every solve), with any kernel. −1 (the default): from 512 batches with the AVX-512 kernel,
  /// never with the others. Below, the batches stay in the core's cache between sweeps, so the
  /// sweeps gain nothing from fewer bytes while the compression in the pack and the expansion
  /// for the closing residual still cost; the AVX2 kernel's per-half lane masks and derivations
  /// cost more than the bytes it saves (micro_pgs's BM_PgsColored, micro_step's BM_StepStages).
  int compact_from_batches = -1;
  /// When set, every solve adds the times of its parts here (PgsColoredProfile; the caller
  /// keeps it alive while the solver is used).
  PgsColoredProfile* profile = nullptr;
};

std::unique_ptr<LcpSolver> make_pgs_colored(const PgsColoredDef& def = {});

/// "nncg-colored": nncg's momentum (Fletcher–Reeves, as "nncg": β = ‖Δf_k‖²/‖Δf_{k−1}‖², a
/// restart when β > 1, the move of λ and of its Δu applied before the next sweep) on
/// pgs-colored's colour-ordered sweeps, which are cheaper per row than "pgs"'s on large
/// problems; the momentum moves the packed λ and the sweeps' Δu (docs/solvers.md
/// "nncg-colored"). Statuses, θ (the sweep's own change, the move excluded) and the returned λ
/// (a projecting sweep's output) as nncg's. With the ordered colouring (the default) a sweep is
/// pgs's while the contact chains fit in 64 colours, so its iterates follow nncg's up to the
/// round-off of β's sums (taken in packed order); beyond, the overflow set is swept last.
/// Problems the kernels do not cover are solved by "nncg", and the message says so.
struct NncgColoredDef {
  /// The sweeps' settings (threads, kernel, colouring), pgs-colored's (default PgsColoredDef{}),
  /// but with the momentum locality_order is off: β's sums run over the packed λ in its order,
  /// which the locality order would make depend on the thread count (the result bits would).
  PgsColoredDef sweep;
  /// The momentum (default true). false: pgs-colored's sweeps alone, its iterates bit for bit
  /// (the reference the momentum is tested against).
  bool momentum = true;
};

std::unique_ptr<LcpSolver> make_nncg_colored(const NncgColoredDef& def = {});

/// True when this build and CPU can run `kernel` (Auto and Scalar: always).
bool pgs_colored_kernel_available(PgsColoredKernel kernel);

/// The kernel Auto sweeps a problem of `single_batches` batches of 8 single contacts with on this
/// CPU (never Auto): AVX-512 where it runs, but on AMD CPUs AVX2 before Zen 5 and, on Zen 5,
/// below 512 batches (docs/lcp.md "pgs-colored").
PgsColoredKernel pgs_colored_auto_kernel(long single_batches = 0);

/// "auto", "avx512", "avx2" or "scalar".
const char* to_string(PgsColoredKernel kernel);

}  // namespace dc
