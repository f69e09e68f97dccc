// builtin-statics: builtin, plus a top-down load propagation for contacts without history:
//   * "up" is −g/|g|; bodies are processed from the highest (largest x·up) to the lowest;
//   * body k carries its weight m_k|g| plus the load L_k handed to it from above;
//   * its support contacts are its closing contacts (gap ≤ [contact] slop + margin) whose force on k
//     points up: s_c = n_c·up for k = body_b (the force on b is +λ n), −n_c·up for k = body_a;
//     only s_c > 0.05 counts (side contacts carry nothing);
//   * λ_c = L_k s_c / Σ s_c'² (vertical components add up to L_k); the other body receives λ_c s_c.
// λ is a force [N] (docs/design.md §2), so a column of circles gets λ_n = the weight above the
// contact. Friction rows get 0; contacts with history keep builtin's λ.
#include <algorithm>
#include <cmath>
#include <numeric>

#include "starters.hpp"

namespace dc {

Eigen::VectorXd statics_guess(const World& w) {
  const BodyState& b = w.bodies();
  const auto& cur = w.contacts();
  const Vec2 g = w.def().world.gravity;
  const double gn = std::sqrt(g.x * g.x + g.y * g.y);
  Eigen::VectorXd out = Eigen::VectorXd::Zero(w.problem().rows());
  if (!(gn > 0) || cur.empty()) return out;
  const Vec2 up{-g.x / gn, -g.y / gn};
  const double closing = w.def().contact.slop + w.def().contact.margin;
  constexpr double kMinSupport = 0.05;

  // Support contacts per body, as (contact, s_c).
  const std::size_t n = b.size();
  std::vector<std::vector<std::pair<int, double>>> support(n);
  for (std::size_t c = 0; c < cur.size(); ++c) {
    const Contact& k = cur[c];
    if (k.gap > closing) continue;
    const double s = dot(k.normal, up);
    if (s > kMinSupport) support[static_cast<std::size_t>(k.body_b)].emplace_back(static_cast<int>(c), s);
    else if (-s > kMinSupport && k.body_a >= 0) support[static_cast<std::size_t>(k.body_a)].emplace_back(static_cast<int>(c), -s);
  }
  std::vector<int> order(n);
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(), [&](int i, int j) {
    return dot(b.position[static_cast<std::size_t>(i)], up) > dot(b.position[static_cast<std::size_t>(j)], up);
  });
  std::vector<double> load(n, 0.0);
  for (const int k : order) {
    const auto ks = static_cast<std::size_t>(k);
    const double L = load[ks] + b.mass[ks] * gn;
    double ss = 0;
    for (const auto& [c, s] : support[ks]) ss += s * s;
    if (!(ss > 0)) continue;  // nothing below: the load is dropped (a falling body)
    for (const auto& [c, s] : support[ks]) {
      const double lam = L * s / ss;
      const ContactConstraint& row = w.constraints()[c];
      out[row.normal_row] = lam;
      const Contact& k2 = cur[static_cast<std::size_t>(c)];
      const int other = k2.body_b == k ? k2.body_a : k2.body_b;
      if (other >= 0) load[static_cast<std::size_t>(other)] += lam * s;
    }
  }
  return out;
}

namespace {

class StaticsWarmStarter final : public WarmStarter {
 public:
  std::string name() const override { return "builtin-statics"; }
  Eigen::VectorXd initial_guess(const StepView& v) override {
    const World& w = v.world;
    Eigen::VectorXd out = statics_guess(w);
    put_previous_lambda_by_key(w, out);
    project_feasible(w.problem(), out);
    return out;
  }
};

}  // namespace

std::unique_ptr<WarmStarter> make_statics_warm_starter(const WarmStartSpec& spec, const WarmStartEnv&) {
  reject_argument(spec);
  return std::make_unique<StaticsWarmStarter>();
}

}  // namespace dc
