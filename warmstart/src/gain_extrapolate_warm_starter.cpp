// builtin-gain-extrapolate[:KERNEL:D:H]: builtin scaled by last step's smoothed load change
// (docs/bench.md "Non-learned baselines"). Per-contact extrapolation is noisy (PGS stops at a
// tolerance, contacts flicker); this estimates sph-gain's smooth gain field from the last two
// solved steps instead of from λ*, and applies it again:
//     N_r(x) = Σ_c W(|x − p_c|) (λ^{t−1}_c,r − λ^{t−2}_c,r) λ^{t−2}_c,r
//     D_r(x) = Σ_c W(|x − p_c|) (λ^{t−2}_c,r)²              (c: contacts of step t−1 seen at t−2)
//     λ⁰_k,r = λ^{t−1}_k,r (1 + bilinear(N_r)(q_k) / bilinear(D_r)(q_k))   (ĝ = 0 where D = 0)
// p_c step t−1's contact points, q_k this step's; new contacts get 0. Projected onto the
// feasible set. Not an oracle. The λ^{t−2} memory is dropped when the world's step index does
// not advance by exactly one between calls.
#include <optional>

#include "dc/sph/sph_splat.hpp"
#include "dc/warmstart/sph_warm_starter.hpp"
#include "starters.hpp"

namespace dc {
namespace {

class GainExtrapolateWarmStarter final : public WarmStarter {
 public:
  GainExtrapolateWarmStarter(const SphTransferDef& def, std::string arg) : def_(def), arg_(std::move(arg)) {}

  std::string name() const override {
    return arg_.empty() ? "builtin-gain-extrapolate" : "builtin-gain-extrapolate:" + arg_;
  }

  Eigen::VectorXd initial_guess(const StepView& v) override {
    const World& w = v.world;
    const auto& cur = w.contacts();
    const auto& prev = w.previous_contacts();
    const bool history = last_step_ >= 0 && w.step_index() == last_step_ + 1;
    Eigen::VectorXd out = Eigen::VectorXd::Zero(w.problem().rows());
    put_previous_lambda_by_key(w, out);  // builtin, unprojected: λ^{t−1} by key
    if (history && !cur.empty() && !prev.empty()) {
      ensure_fields(w);
      // The field of the change t−2 → t−1, splatted at step t−1's contact points.
      const std::vector<int> m2 = match_contacts_by_key(older_, prev);
      points_.clear();
      values_.clear();
      for (std::size_t c = 0; c < prev.size(); ++c) {
        if (m2[c] < 0) continue;
        const Contact& p1 = prev[c];
        const Contact& p2 = older_[static_cast<std::size_t>(m2[c])];
        points_.push_back(p1.point);
        values_.insert(values_.end(), {(p1.lambda_n - p2.lambda_n) * p2.lambda_n,
                                       (p1.lambda_t - p2.lambda_t) * p2.lambda_t, p2.lambda_n * p2.lambda_n,
                                       p2.lambda_t * p2.lambda_t});
      }
      if (!points_.empty()) {
        splat_to_grid(*kernel_, points_, values_, *fields_, nullptr);
        points_.clear();
        for (const Contact& c : cur) points_.push_back(c.point);
        back_.resize(4 * cur.size());
        gather_bilinear(*fields_, points_, back_);
        const ContactConstraints& cons = w.constraints();
        for (std::size_t c = 0; c < cur.size(); ++c) {
          const int k = static_cast<int>(c);
          const auto [gn, gt] = read_gains(back_, c);
          cons.put(k, cons.lambda_n(out, k) * (1 + gn), cons.lambda_t(out, k) * (1 + gt), out);
        }
      }
    }
    project_feasible(w.problem(), out);
    older_ = prev;
    last_step_ = w.step_index();
    return out;
  }

 private:
  // The kernel and the four fields cover the scene's box: (re)built when the box changes.
  void ensure_fields(const World& w) {
    if (kernel_ && fields_->def().width == w.def().world.width && fields_->def().height == w.def().world.height)
      return;
    SphGridDef g = def_.grid;
    g.width = w.def().world.width;
    g.height = w.def().world.height;
    g.channels = 4;
    fields_.emplace(g);
    kernel_.emplace(def_.kernel, def_.support);
  }

  SphTransferDef def_;
  std::string arg_;
  std::optional<SphKernel> kernel_;
  std::optional<SphGrid> fields_;  // N_n, N_t, D_n, D_t
  std::vector<Contact> older_;     // previous_contacts() of the last call: step t−2 now
  int last_step_ = -1;
  std::vector<Vec2> points_;
  std::vector<double> values_, back_;
};

}  // namespace

std::unique_ptr<WarmStarter> make_gain_extrapolate_warm_starter(const WarmStartSpec& spec, const WarmStartEnv&) {
  return std::make_unique<GainExtrapolateWarmStarter>(parse_sph_options(spec), spec.arg);
}

}  // namespace dc
