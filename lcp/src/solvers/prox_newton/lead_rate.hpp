#pragma once
// The lead stage's stop rule (ProxNewtonDef::lead_sweeps): nncg sweeps from the guess go on
// while their observed rate reaches the target within the sweeps allowed. nncg converges
// linearly at a rate set by the pile (fast on loose, small scenes; far too slow on deep settled
// piles), so a few chunks tell whether it gets there at all; the Newton passes take over
// from the best iterate when it does not.
namespace dc::solvers::prox {

class LeadRate {
 public:
  /// `start` [N]: the hard residual at the guess.
  explicit LeadRate(double start) : start_(start) {}

  /// After a chunk of `chunk` sweeps with `done` sweeps in all: true when the best hard
  /// residual `best` [N] fell and, at the rate q per chunk since the end of the first chunk
  /// (from the guess for the first chunk alone), reaches `target` [N] within `cap` sweeps.
  [[nodiscard]] bool go_on(double best, double target, int done, int chunk, int cap);

 private:
  double start_;        // hard residual at the guess [N]
  double first_ = 0;    // best hard residual after the first chunk [N]
  double last_ = 0;     // best hard residual after the previous chunk [N]
  int chunks_ = 0;
};

}  // namespace dc::solvers::prox
