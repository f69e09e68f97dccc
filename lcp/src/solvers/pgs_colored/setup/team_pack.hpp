#pragma once
// Private to "pgs-colored" (pgs_colored_layout.hpp): the pack of every batch on the members of the
// calling thread's team (dc/core/work_team.hpp). The sources are staged on the team
// (stage_sources, each member a block of the contacts), then each colour range's batches are
// split into one block per member, as the sweeps split them (sweep_team.hpp), and handed out in
// parts of at most kPackChunk batches: member t first packs its block of every range, in range
// order, then takes what is left of the others' blocks from their back. Each batch is written
// by one member from its own sources into its own slots (batch, row_of, diag, λ⁰), so the
// packed problem is the same bits on every thread count and schedule.
#include <vector>

#include <Eigen/Core>

#include "dc/core/work_team.hpp"
#include "dc/lcp/lcp_problem.hpp"
#include "solvers/pgs_colored/pgs_colored_layout.hpp"

namespace dc::colored {

/// Batches per part of the pack: enough that a part's claim (one atomic operation) is a small
/// share of its work, few enough that a member that comes free late still finds parts to take.
constexpr int kPackChunk = 16;

/// The jobs of `ranges` (single batches numbered from 0, pair batches from `batches`) as parts of
/// at most `chunk` jobs, member-major: member 0's block of each range in range order (block t of
/// a range of n batches: [begin + n·t/threads, begin + n·(t + 1)/threads)), then member 1's, …
/// Every job is in exactly one part; the parts of one member are contiguous in `parts`, so
/// for_parts's contiguous block of the parts per member is about that member's blocks.
void pack_parts(const std::vector<Range>& ranges, int batches, int threads, int chunk, std::vector<PackPart>& parts);

/// Stages the sources (stage_sources) and fills every batch and pair batch of the laid-out `prep`
/// (fill_compact into the compact layout when `compact`, else fill_batch; fill_pair; each
/// over-relaxed by ω as it is filled) on up to `threads` members of the calling thread's team;
/// `side`, when given, runs as one more part of the fill's run (Δu⁰: a serial pass over J that
/// one member takes while the others pack). Sets prep.compact_on (every batch compressed
/// exactly; else every batch is packed full, serially). The sources are staged from `stage_from`
/// ordered positions on (stage_sources' `from`). The same bits for every thread count.
void pack_batches(const LcpProblem& p, const Eigen::Ref<const Eigen::VectorXd>& lambda, double omega, bool compact,
                  Prepared& prep, double* lp, double* other, int threads, const PartJob* side = nullptr,
                  int stage_from = kStageFrom);

}  // namespace dc::colored
