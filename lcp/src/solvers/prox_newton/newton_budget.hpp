#pragma once
// prox-newton's Newton-part budget (ProxNewtonDef::newton_budget): the factorisations the first
// Newton part may make without progress before nncg takes over from the best iterate. Progress
// is a fall of the best hard residual of the whole solve (every part's iterates, the lead
// stage's included) at least `gain`-fold since the count last started, so a part that creeps
// down a few percent per factorisation runs out of it.
#include <algorithm>
#include <cmath>

namespace dc::solvers::prox {

class NewtonBudget {
 public:
  /// `budget` factorisations (0: none), `gain` (≥ 1) the fall that restarts the count.
  NewtonBudget(int budget, double gain) : budget_(budget), gain_(gain) {}

  /// An iterate of any part with hard residual `res` [N], seen after `factorizations` in all.
  void progress(double res, int factorizations) {
    if (!(res < best_)) return;
    best_ = res;
    if (!(res * gain_ <= ref_)) return;
    ref_ = res;
    base_ = std::max(base_, factorizations);
  }

  /// A budgeted part begins (`on`: the budget applies to it) after `factorizations` in all.
  void begin(bool on, int factorizations) {
    on_ = on && budget_ > 0;
    base_ = factorizations;
    ref_ = best_;
  }
  /// The budgeted part ended: later parts run without a budget.
  void end() { on_ = false; }

  /// True once the budgeted part made `budget` factorisations since its start or the last
  /// progress, `factorizations` made in all; stays true for that part.
  bool over(int factorizations) {
    if (!on_) return false;
    if (factorizations - base_ >= budget_) spent_ = true;
    return spent_;
  }
  /// The budgeted part ran out of its budget.
  [[nodiscard]] bool spent() const { return spent_; }
  /// A budget applies to the part in progress.
  [[nodiscard]] bool on() const { return on_; }

 private:
  int budget_;
  double gain_;
  double best_ = INFINITY;  // best hard residual of the whole solve [N]
  double ref_ = INFINITY;   // best hard residual where the count last started [N]
  int base_ = 0;            // factorisations where the count last started
  bool on_ = false;
  bool spent_ = false;
};

}  // namespace dc::solvers::prox
