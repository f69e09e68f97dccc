#pragma once
// The lead stage's stop rule (ProxNewtonDef::lead_sweeps, lead_window, lead_window_gain): nncg
// sweeps from the guess go on while their best hard residual keeps falling over a window of
// chunks. nncg's residual is not monotone: on loose and mid-sized piles it climbs for hundreds of
// sweeps between new bests while it still converges linearly overall, so a single chunk without a
// new best, or the rate of the first chunks, says little. On deep settled piles it falls by far
// less than 2-fold over a window, and the Newton passes take over from the best iterate.
#include <vector>

namespace dc::solvers::prox {

class LeadRate {
 public:
  /// `start` [N]: the hard residual at the guess. `window` chunks (0: the rate rule below);
  /// `gain` (> 1): the fall of the best hard residual asked over a window.
  LeadRate(double start, int window, double gain) : start_(start), window_(window), gain_(gain) {}

  /// After a chunk of `chunk` sweeps with `done` sweeps in all, the best hard residual `best`
  /// [N] so far: true to run another chunk. False once `best` ≤ `target` [N], `done` ≥ `cap`, or
  /// `best` is not finite and > 0; otherwise
  ///   * window > 0: true when the best fell at least gain-fold over the last `window` chunks,
  ///     best·gain ≤ the best `window` chunks earlier; during the first `window` chunks pro rata
  ///     from the start, best·gain^(n/window) ≤ start after chunk n (a stage that gains little
  ///     from the start, as from an iterate nncg already polished, hands over early);
  ///   * window = 0 (the rate rule): true when this chunk lowered the best and, at the rate q per
  ///     chunk since the end of the first chunk (from the start for the first chunk alone), the
  ///     target is reached within `cap` sweeps.
  [[nodiscard]] bool go_on(double best, double target, int done, int chunk, int cap);

 private:
  [[nodiscard]] bool rate_reaches(double best, double target, int done, int chunk, int cap) const;

  double start_;              // hard residual at the guess [N]
  int window_;                // chunks per window (0: the rate rule)
  double gain_;               // fall asked over a window
  std::vector<double> best_;  // best hard residual after each chunk [N]
};

}  // namespace dc::solvers::prox
