#pragma once
// The lead stage's stop rule (ProxNewtonDef::lead_sweeps, lead_window, lead_window_gain): nncg
// sweeps from the guess go on while their best hard residual keeps falling over a window of
// chunks. nncg's residual is not monotone: on loose and mid-sized piles it climbs for hundreds of
// sweeps between new bests while it still converges linearly overall, so a single chunk without a
// new best, or the rate of the first chunks, says little. On deep settled piles it falls by far
// less than 2-fold over a window, and the Newton passes take over from the best iterate.
#include <vector>

namespace dc::solvers::prox {

/// The lead stage's window [chunks] on a problem of `bodies` bodies (ProxNewtonDef::lead_window,
/// lead_window_bodies): `window` up to `reference` bodies, and window·√(bodies/reference),
/// rounded, above (reference ≤ 0: `window` always). A Newton iteration's factorisation of the
/// body-space H (3 unknowns per body, a planar contact graph) costs O(n^1.5) under nested
/// dissection while an nncg sweep costs O(n): the sweeps worth running before the Newton part
/// grow with the ratio, √n. window = 0 (the rate rule) stays 0.
[[nodiscard]] int lead_window_chunks(int window, double reference, int bodies);

class LeadRate {
 public:
  /// `start` [N]: the hard residual at the guess. `window` chunks (0: the rate rule below);
  /// `gain` (> 1): the fall of the best hard residual asked over a window.
  LeadRate(double start, int window, double gain) : start_(start), window_(window), gain_(gain) {}
  /// With `stall` > 0: also false once `stall` chunks in a row brought no new best (the stall
  /// rule, ProxNewtonDef::lead_stall_chunks; 0: none).
  LeadRate(double start, int window, double gain, int stall) : LeadRate(start, window, gain) { stall_ = stall; }

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

  /// The fall of the best hard residual over the last `window` chunks (the best then over the
  /// best now; within the first window, the fall from the start scaled to a window); 1 before
  /// the first chunk or with the rate rule (window = 0).
  [[nodiscard]] double window_fall() const;

 private:
  [[nodiscard]] bool rate_reaches(double best, double target, int done, int chunk, int cap) const;

  double start_;              // hard residual at the guess [N]
  int window_;                // chunks per window (0: the rate rule)
  double gain_;               // fall asked over a window
  std::vector<double> best_;  // best hard residual after each chunk [N]
  int stall_ = 0;             // chunks without a new best that end the stage (0: no such rule)
  int since_best_ = 0;        // chunks since the last new best
};

}  // namespace dc::solvers::prox
