// gate:INNER and gate-l2:INNER: a safeguard around any starter. Each step both builtin's
// guess and INNER's are scored by the natural-map residual of the step's LCP (docs/design.md §2,
// natural_residual: r_i = λ_i − mid(lo_i, λ_i − w_i, hi_i), w = Aλ + b) and the one with the
// smaller score is returned — builtin on a tie, so a starter that is no better is never used.
//   gate     scores by max_i |r_i| (the solver's own tolerance measure θ);
//   gate-l2  scores by ‖r‖₂ (the whole error, not its worst contact: PGS's sweep count is set
//            by the slow, spread-out part of the error more than by one bad contact).
// Why: a learned model that is good on its family can be harmful off it (models/impact.h5
// needs more sweeps than builtin on the seed pile, docs/research.md); the gate keeps such a
// model from ever starting PGS further from the solution than builtin by its own measure.
// Cost: two matrix-free residual evaluations (each O(nnz J), ≈ one PGS sweep) on top of
// INNER's guess; timed with the guess.
#include "dc/lcp/lcp_problem.hpp"
#include "starters.hpp"

namespace dc {
namespace {

/// The natural-map residual of λ in the chosen norm.
double residual_score(const LcpProblem& p, const Eigen::VectorXd& lambda, GateNorm norm) {
  return norm == GateNorm::Max ? natural_residual(p, lambda) : natural_residual_l2(p, lambda);
}

class GateWarmStarter final : public WarmStarter {
 public:
  GateWarmStarter(std::unique_ptr<WarmStarter> inner, std::string base, GateNorm norm)
      : inner_(std::move(inner)), base_(std::move(base)), norm_(norm) {}
  std::string name() const override { return base_ + ":" + inner_->name(); }
  bool uses_oracle() const override { return inner_->uses_oracle(); }
  double oracle_ms() const override { return inner_->oracle_ms(); }
  void observe(const StepView& v, const Eigen::VectorXd& solved) override { inner_->observe(v, solved); }

  Eigen::VectorXd initial_guess(const StepView& v) override {
    const World& w = v.world;
    Eigen::VectorXd candidate = inner_->initial_guess(v);
    Eigen::VectorXd fallback = builtin_guess(w);
    if (candidate.size() != fallback.size()) return fallback;  // a broken inner never wins
    const double inner_score = residual_score(w.problem(), candidate, norm_);
    const double builtin_score = residual_score(w.problem(), fallback, norm_);
    return inner_score < builtin_score ? candidate : fallback;
  }

 private:
  std::unique_ptr<WarmStarter> inner_;
  std::string base_;
  GateNorm norm_;
};

}  // namespace

std::unique_ptr<WarmStarter> make_gate_warm_starter(const WarmStartSpec& spec, const WarmStartEnv& env) {
  const GateOptions o = parse_gate_options(spec);
  if (!env.registry) throw InvalidArgument("warm starter '" + spec.full() + "': built without a registry");
  return std::make_unique<GateWarmStarter>(env.registry->make(o.inner, env), spec.name, o.norm);
}

}  // namespace dc
