#pragma once
// Private to "pgs-colored" (dc/lcp/pgs_colored.hpp): the packed problem and its set-up. layout()
// orders the contacts by colour into batches of single contacts (Batch) and of two-point
// manifolds (PairBatch: the two contacts of one body pair with one normal in one lane, solved
// with the 2 × 2 normal block as "pgs" does); fill_batch / fill_pair pack the rows (4 lanes per
// AVX2 register where the CPU has it, pgs_colored_pack_simd.hpp; the same bits). The sweep
// driver is pgs_colored.cpp, the kernels pgs_colored_{scalar,avx2,avx512}.cpp.
//
// Permuted λ: the single batches' slots first (16 per batch: 8 λ_n, 8 λ_t), then the pair
// batches' from Prepared::pair_base (32 per batch: λ_n0, λ_t0, λ_n1, λ_t1, 8 each).
#include <algorithm>
#include <cstdint>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "dc/lcp/lcp_problem.hpp"
#include "solvers/pgs_colored/coloring/contact_coloring.hpp"
#include "solvers/pgs_colored/compact/compact_batch.hpp"
#include "solvers/pgs_colored/coloring/ordered_coloring.hpp"
#include "solvers/pgs_colored/pgs_colored_batch.hpp"
#include "solvers/pgs_colored/setup/body_numbering.hpp"

namespace dc::colored {

/// Batches [begin, end) of one colour (independent: may run in any order or in parallel),
/// or of the overflow set (serial = true: one contact or manifold per batch, in order); of
/// single contacts, or of pairs (pairs = true: indices into Prepared::pairs).
struct Range {
  int begin, end;
  bool serial;
  bool pairs;
};

/// Jobs [begin, end) of the pack (setup/team_pack.hpp): single batch bi is job bi, pair batch pi
/// job batches + pi.
struct PackPart {
  int begin, end;
};

/// The sources of one single lead contact with friction whose rows have the usual storage
/// (pack_rows_simd's), copied by stage_sources to its ordered position: the J entries of its
/// normal and tangent rows (slots 3–5 +0 without a second body), b and λ⁰ of both rows, μ, its
/// rows and the J columns of its bodies (a: the lower body, bb: the other, −1 for none).
struct StagedRows {
  double vn[6], vt[6];
  double bn, bt, ln, lt, mu;
  int rn, rt, a, bb;
};
static_assert(sizeof(StagedRows) == 19 * sizeof(double));

/// The packed problem and the solve's buffers; kept by the solver between solves.
struct Prepared {
  std::vector<Batch> batches;
  /// The batches in the compact layout (compact/compact_batch.hpp), which the sweeps read when
  /// compact_on: set by the pack when every batch compressed exactly.
  std::vector<CompactBatch> compact;
  bool compact_on = false;
  /// The compact pack on AVX-512 (pack_compact_simd's `wide`): set by the solver when its kernel
  /// is the AVX-512 one, so that each kernel's tests also run its ISA's pack.
  bool wide_pack = false;
  std::vector<PairBatch> pairs;
  std::vector<Range> ranges;
  std::vector<int> row_of;    // permuted slot → LCP row (−1: padding or no tangent row)
  std::vector<double> diag;   // permuted slot → A_ii of its row (1: padding; the packed residual)
  std::vector<int> order;     // lead contact of each lane, slot after slot
  std::vector<int> start;     // first lane of each slot: 2·colour (singles), 2·colour + 1 (pairs); overflow last
  std::vector<int> batch_of;  // per slot: its first batch (single slots) or pair batch (pair slots)
  std::vector<int> slot_of_batch, slot_of_pair;  // per batch / pair batch: its slot
  std::vector<int> partner;   // per contact: its manifold's second contact, −2 when it is one, else −1
  std::vector<int> position;  // scratch of stage_sources: per lead contact its ordered position
  std::vector<StagedRows, Eigen::aligned_allocator<StagedRows>> staged;  // per ordered position (stage_sources)
  std::vector<std::uint8_t> usable;  // per ordered position: 1 when staged holds its sources
  bool staged_now = false;           // staged and usable belong to this solve's problem and λ⁰
  std::vector<int> next_partner;  // scratch of layout(): this problem's pairs before they replace `partner`
  std::vector<int> count;         // scratch of layout()'s counting sort
  std::vector<PackPart> pack_parts;  // scratch of pack_batches (setup/team_pack.hpp)
  std::vector<std::uint8_t> dynamic;
  std::vector<int> failed;    // per batch, then per pair batch: its first contact that cannot be packed, or −1
  std::vector<double, Eigen::aligned_allocator<double>> du;
  Eigen::VectorXd jt;    // Jᵀλ (scratch of the products, pgs_colored_products.hpp)
  Eigen::VectorXd lp, other;  // storage of the permuted λ: handed to the sweeps, returned after them
  int body_entries = 0;  // kStride·bodies; the zero body follows
  int pair_base = 0;     // first permuted slot of the pair batches (2·W·batches)
  bool j_finite = false;  // every J entry finite (values_finite): the products skip rows with λ_i = 0
  std::uint64_t generation = 0;  // the colouring (ContactColoring::generation) laid out; 0: none
  /// Body → Δu slot and the contacts' key order (setup/body_numbering.hpp); the identity and
  /// contact order without locality.
  BodyNumbering numbering;
  /// The offset of body k's Δu in du (kStride per slot).
  [[nodiscard]] int du_entry(int k) const { return kStride * numbering.slot[static_cast<size_t>(k)]; }
};

/// Orders the contacts by colour and lays out the batches (O(contacts), the colouring and the
/// counting sort on `threads` threads; the same layout for every thread count). The colours are
/// `ordered`'s (ordered_coloring.hpp) when it is given, else `colorer`'s. With `locality` the
/// bodies' Δu slots are their locality numbers and each colour's contacts are in key order
/// (setup/body_numbering.hpp; the same result bits), else Δu slot = body and contact order.
/// Returns an error (the reason "pgs" runs instead) when a normal row has bounds other than
/// [0, ∞). `coloring_s` (timing only): when set, the thread CPU seconds of the colouring are
/// added to it.
std::string layout(const LcpProblem& p, ContactColorer& colorer, OrderedColorer* ordered, int threads,
                   Prepared& out, double* coloring_s = nullptr, bool locality = true);

/// Fills batch `bi` (into *into, else out.batches[bi]) from the ordered contacts and its 2·W
/// entries of the permuted λ⁰ (lp and other; 0 for padding); records in out.failed[bi] the first
/// of its contacts whose rows cannot be packed (another body, A_ii not finite and > 0).
void fill_batch(const LcpProblem& p, const Eigen::Ref<const Eigen::VectorXd>& lambda, Prepared& out, int bi, double* lp,
                double* other, Batch* into = nullptr);
/// The same for pair batch `pi` (4·W entries from out.pair_base + 4·W·pi; failures at
/// out.failed[batches + pi]).
void fill_pair(const LcpProblem& p, const Eigen::Ref<const Eigen::VectorXd>& lambda, Prepared& out, int pi, double* lp, double* other);

/// The first contact (in batch order) whose rows cannot be packed, as the reason "pgs" runs.
std::string first_failure(const Prepared& out);

/// Copies the sources of the single lead contacts (StagedRows) to their ordered positions in one
/// pass in the contacts' own order, so that fill_batch reads them in batch order instead of
/// gathering J, b and λ⁰ in colour order, which strides across arrays larger than the cache once
/// per colour. fill_batch packs the same bits either way. Stages only problems of at least
/// `from` ordered positions and only with AVX2 (pack_rows_staged); sets out.staged_now.
/// kStageFrom is about the count of positions whose J rows, b and λ⁰ outgrow a core's L2 cache:
/// below it the gathered sources stay in cache from colour to colour, and a staging pass (its
/// 152-byte records written at scattered positions, then read again) would only add traffic;
/// above it each colour's gathers stride across memory once per colour, and the pack from the
/// staged records in batch order (compact batches straight from them, pack_compact_staged) is
/// the cheaper one (micro_step BM_ColoredPackSettled, BM_ColoredPack with evict 4). On up to
/// `threads` members of the calling thread's team: each member the positions of a block of the
/// ordered contacts, then the records of a block of the contacts (each record written by one
/// member: the same records on every thread count).
constexpr int kStageFrom = 1 << 14;
void stage_sources(const LcpProblem& p, const Eigen::Ref<const Eigen::VectorXd>& lambda, Prepared& out,
                   int from = kStageFrom, int threads = 1);

/// Lane count and first ordered lane of batch `local` of slot k (the overflow slots, the last
/// two: one lane per batch).
inline void lanes_of(const Prepared& out, int k, int local, int& s0, int& lanes) {
  const int slots = static_cast<int>(out.start.size()) - 1;
  const int per = k >= slots - 2 ? 1 : W;
  s0 = out.start[static_cast<size_t>(k)] + local * per;
  lanes = std::min(per, out.start[static_cast<size_t>(k) + 1] - s0);
}

/// The rows and J columns of the W lanes whose lead contacts are order[0, lanes) (padding lanes
/// on lane 0's contact): normal and tangent rows, a = 3·(lower body) (the only body when there is
/// one), bb = 3·(other body) or −1. False when a contact has no friction (then the batch is not
/// packed from these arrays).
inline bool lane_rows(const LcpProblem& p, const int* order, int lanes, int (&rn)[W], int (&rt)[W], int (&a)[W],
                      int (&bb)[W]) {
  for (int lane = 0; lane < W; ++lane) {
    const ContactConstraint& k = p.constraints[order[lane < lanes ? lane : 0]];
    if (!k.has_friction()) return false;
    const int first = k.has_body_a() ? std::min(k.body_a, k.body_b) : k.body_b;
    const int second = k.has_body_a() ? std::max(k.body_a, k.body_b) : -1;
    a[lane] = 3 * first;
    bb[lane] = second < 0 ? -1 : 3 * second;
    rn[lane] = k.normal_row;
    rt[lane] = k.tangent_row;
  }
  return true;
}

// ---- pgs_colored_stage.cpp's parts of fill_batch ------------------------------------------
/// Lane `lane` of batch B (a Batch or CompactBatch) and its rows: the Δu offsets and store flags
/// of bodies `first` and `second` (−1: none), μ, the normal and tangent rows.
template <class AnyBatch>
inline void put_lane(const Prepared& out, AnyBatch& B, int* row_of, int lane, int first, int second, double mu, int rn,
                     int rt) {
  const bool da = out.dynamic[static_cast<size_t>(first)] != 0;
  const bool db = second >= 0 && out.dynamic[static_cast<size_t>(second)] != 0;
  B.mu[lane] = mu;
  B.la[lane] = da ? out.du_entry(first) : out.body_entries;
  B.lb[lane] = db ? out.du_entry(second) : out.body_entries;
  B.ka[lane] = da ? 1 : 0;
  B.kb[lane] = db ? 1 : 0;
  row_of[lane] = rn;
  row_of[W + lane] = rt;
}
/// fill_batch's rows and bodies of batch (s0, lanes) by pack_rows_staged from the staged sources;
/// false when they are not staged (out.staged_now, out.usable).
bool pack_batch_staged(const LcpProblem& p, const Prepared& out, int s0, int lanes, Batch& B, int* row_of,
                       double* diag_n, double* diag_t, bool& ok_n, bool& ok_t);
/// The batch's 2·W entries of the permuted λ⁰ from the staged sources (0 for padding).
void staged_lambda(const Prepared& out, int s0, int lanes, double* lp, double* other);

}  // namespace dc::colored
