#include "dc/research/pgs_trainer.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <string>
#include <tuple>

#include "dc/core/error.hpp"
#include "dc/core/rng.hpp"
#include "dc/learning/optimizer.hpp"
#include "dc/learning/trainer.hpp"
#include "dc/research/least_squares_field.hpp"

namespace dc {

const char* to_string(PgsLoss loss) {
  switch (loss) {
    case PgsLoss::Residual: return "pgs-residual";
    case PgsLoss::Distance: return "pgs-distance";
    case PgsLoss::Field: return "pgs-field";
  }
  return "?";
}

PgsLoss parse_pgs_loss(std::string_view text) {
  for (const PgsLoss l : {PgsLoss::Residual, PgsLoss::Distance, PgsLoss::Field})
    if (text == to_string(l)) return l;
  throw ConfigError("--loss '" + std::string(text) + "': expected regression, pgs-residual, pgs-distance or pgs-field");
}

PgsLoss validation_loss(PgsLoss loss) { return loss == PgsLoss::Field ? PgsLoss::Distance : loss; }

// ---- projection of the guess ------------------------------------------------------------

Eigen::VectorXd GuessProjection::forward(const LcpProblem& p, const Eigen::VectorXd& x) {
  const int n = p.rows();
  Eigen::VectorXd lam = x;
  piece_.assign(static_cast<std::size_t>(n), 0);
  // project_feasible's order and clamps (lcp/src/problem/lcp_problem.cpp).
  for (int i = 0; i < n; ++i) {
    if (!std::isfinite(lam[i])) {
      lam[i] = 0.0;
      piece_[static_cast<std::size_t>(i)] = 1;
    }
    if (!p.is_friction_row(i)) {
      const double v = std::clamp(lam[i], p.lo[i], p.hi[i]);
      if (v != lam[i]) piece_[static_cast<std::size_t>(i)] = 1;
      lam[i] = v;
    }
  }
  for (int i = 0; i < n; ++i) {
    if (!p.is_friction_row(i)) continue;
    const double lo = p.lower(i, lam), hi = p.upper(i, lam);
    std::int8_t& pc = piece_[static_cast<std::size_t>(i)];
    if (pc == 1) {
      lam[i] = std::clamp(lam[i], lo, hi);
    } else if (!(hi > 0.0)) {
      lam[i] = std::clamp(lam[i], lo, hi);
      pc = 1;
    } else if (lam[i] < lo) {
      lam[i] = lo;
      pc = 3;
    } else if (lam[i] > hi) {
      lam[i] = hi;
      pc = 2;
    }
  }
  return lam;
}

Eigen::VectorXd GuessProjection::backward(const LcpProblem& p, const Eigen::VectorXd& g) const {
  Eigen::VectorXd out = g;
  const int n = p.rows();
  for (int i = 0; i < n; ++i) {  // friction rows first: they feed their normal rows' gradient
    if (!p.is_friction_row(i)) continue;
    const int nr = p.normal_row[static_cast<std::size_t>(i)];
    switch (piece_[static_cast<std::size_t>(i)]) {
      case 0: break;
      case 1: out[i] = 0.0; break;
      case 2: out[nr] += p.mu[i] * g[i]; out[i] = 0.0; break;
      case 3: out[nr] -= p.mu[i] * g[i]; out[i] = 0.0; break;
    }
  }
  for (int i = 0; i < n; ++i)
    if (!p.is_friction_row(i) && piece_[static_cast<std::size_t>(i)] == 1) out[i] = 0.0;
  return out;
}

// ---- objective ----------------------------------------------------------------------------

PgsObjective::PgsObjective(const PgsSample& sample, PgsLoss loss, int unroll, double floor, int field_iterations)
    : s_(sample), loss_(loss), unroll_(unroll), eps_(sample.problem.rows() * floor * floor), pgs_(sample.problem) {
  if (unroll < 0) throw InvalidArgument("PgsObjective: unroll must be >= 0");
  if (loss != PgsLoss::Residual && sample.lambda_star.size() != sample.problem.rows())
    throw InvalidArgument(std::string("PgsObjective: the sample has no lambda_star for the ") + to_string(loss) + " loss");
  if (loss == PgsLoss::Field) {
    field_ = least_squares_correction_grid(sample, field_iterations);
    // The nodes some contact reads (Rᵀ 1 ≠ 0): elsewhere the output never reaches PGS, and
    // regressing it there (on G* = 0) would dominate the samples with few contacts.
    const std::vector<double> ones(2 * static_cast<std::size_t>(sample.readback.points()), 1.0);
    std::vector<float> seen(field_.size(), 0.0f);
    sample.readback.adjoint(ones, seen.data());
    double sq = 0;
    for (std::size_t i = 0; i < field_.size(); ++i)
      if (seen[i] != 0.0f) {
        seen_.push_back(static_cast<std::uint32_t>(i));
        sq += double(field_[i]) * double(field_[i]);
      }
    builtin_loss_ = sq;
    eps_ = static_cast<double>(std::max<std::size_t>(seen_.size(), 1)) * floor * floor;  // f per seen grid entry
    return;
  }
  GuessProjection proj;
  builtin_loss_ = loss_and_grad(proj.forward(s_.problem, s_.lambda_prev), nullptr);
}

double PgsObjective::loss_and_grad(const Eigen::VectorXd& lambda0, Eigen::VectorXd* dlam0) {
  pgs_.forward(lambda0, unroll_);
  Eigen::VectorXd dl = Eigen::VectorXd::Zero(pgs_.rows());
  Eigen::VectorXd du = Eigen::VectorXd::Zero(pgs_.velocity_entries());
  const double L = loss_ == PgsLoss::Residual ? pgs_.residual_loss(dl, du) : pgs_.distance_loss(s_.lambda_star, dl);
  if (dlam0) *dlam0 = pgs_.backward(dl, loss_ == PgsLoss::Residual ? du : Eigen::VectorXd());
  return L;
}

Eigen::VectorXd PgsObjective::initial_guess(const float* grid) {
  v_.resize(2 * static_cast<std::size_t>(s_.readback.points()));
  s_.readback.forward(grid, v_);
  return proj_.forward(s_.problem, s_.problem.constraints.scatter(v_) + s_.lambda_prev);
}

double PgsObjective::evaluate(const float* grid, float* dgrid) {
  if (loss_ == PgsLoss::Field) {  // L = Σ_seen (G − G*)², dJ/dG = 2 (G − G*) / (L + ε) on the seen nodes
    double L = 0;
    for (const std::uint32_t i : seen_) L += (double(grid[i]) - field_[i]) * (double(grid[i]) - field_[i]);
    last_loss_ = L;
    if (dgrid)
      for (const std::uint32_t i : seen_) dgrid[i] += static_cast<float>(2.0 * (double(grid[i]) - field_[i]) / (L + eps_));
    return std::log(L + eps_) - std::log(builtin_loss_ + eps_);
  }
  const Eigen::VectorXd lambda0 = initial_guess(grid);
  Eigen::VectorXd dlam0;
  last_loss_ = loss_and_grad(lambda0, dgrid ? &dlam0 : nullptr);
  const double J = std::log(last_loss_ + eps_) - std::log(builtin_loss_ + eps_);
  if (dgrid) {
    dlam0 /= last_loss_ + eps_;
    const Eigen::VectorXd dx = proj_.backward(s_.problem, dlam0);
    s_.problem.constraints.gather(dx, dv_);
    s_.readback.adjoint(dv_, dgrid);
  }
  return J;
}

// ---- training -----------------------------------------------------------------------------

void PgsTrainDef::validate() const {
  if (unroll < 1) throw ConfigError("--unroll must be >= 1");
  if (epochs < 1) throw ConfigError("--epochs must be >= 1");
  if (batch < 1) throw ConfigError("--batch must be >= 1");
  if (!(learning_rate > 0) || !std::isfinite(learning_rate)) throw ConfigError("--lr must be > 0");
  if (!(momentum >= 0 && momentum < 1)) throw ConfigError("--momentum must be in [0, 1)");
  if (!(weight_decay >= 0)) throw ConfigError("--weight-decay must be >= 0");
  if (!(validation_fraction >= 0 && validation_fraction < 1)) throw ConfigError("--val must be in [0, 1)");
  if (!(time_limit >= 0)) throw ConfigError("--time-limit must be >= 0");
  if (!(floor > 0) || !std::isfinite(floor)) throw ConfigError("--pgs-floor must be > 0");
  if (!(clip >= 0)) throw ConfigError("--clip must be >= 0");
  if (field_iterations < 1) throw ConfigError("--field-iterations must be >= 1");
}

std::vector<int> pgs_validation_simulations(std::span<const PgsSample> samples, const PgsTrainDef& def) {
  std::vector<TrainingSample> ids(samples.size());
  for (std::size_t i = 0; i < samples.size(); ++i) ids[i].simulation = samples[i].simulation;
  Rng rng(def.seed);
  return Trainer::pick_validation_simulations(ids, def.validation_fraction, rng);
}

namespace {

/// z = y·σ_c + m_c and G = s·sinh(z) (or z when s = 0), with dG/dy = s·cosh(z)·σ_c.
void expand_output(const float* y, int C, std::size_t P, const ChannelStats& st, double s, float* G, float* dGdy) {
  for (int c = 0; c < C; ++c) {
    const double sd = st.std[static_cast<std::size_t>(c)], m = st.mean[static_cast<std::size_t>(c)];
    for (std::size_t p = 0; p < P; ++p) {
      const std::size_t k = static_cast<std::size_t>(c) * P + p;
      const double z = double(y[k]) * sd + m;
      const float g = static_cast<float>(s > 0 ? s * std::sinh(z) : z);
      const float dg = static_cast<float>(s > 0 ? s * std::cosh(z) * sd : sd);
      // An overflowing output (inf) is read back as 0 by the projection: no gradient through it.
      const bool ok = std::isfinite(g) && std::isfinite(dg);
      G[k] = ok ? g : 0.0f;
      if (dGdy) dGdy[k] = ok ? dg : 0.0f;
    }
  }
}

}  // namespace

std::pair<double, double> pgs_objective_mean(Model& model, std::span<const PgsSample> samples,
                                             std::span<const std::size_t> idx, const PgsTrainDef& def) {
  if (idx.empty()) return {std::numeric_limits<double>::quiet_NaN(), 0.0};
  double sum = 0;
  int better = 0;
  for (const std::size_t i : idx) {
    const Tensor G = model.predict(samples[i].features);
    PgsObjective obj(samples[i], validation_loss(def.loss), def.unroll, def.floor);
    const double J = obj.evaluate(G.data(), nullptr);
    sum += J;
    better += J < 0;
  }
  return {sum / static_cast<double>(idx.size()), static_cast<double>(better) / static_cast<double>(idx.size())};
}

std::vector<PgsEpochReport> train_through_pgs(Model& model, std::span<const PgsSample> samples, const PgsTrainDef& def,
                                              const std::function<bool(const PgsEpochReport&)>& on_epoch,
                                              const std::function<bool()>& keep_going) {
  def.validate();
  if (!is_corrective(model.grid().labels.kind))
    throw ConfigError("training through PGS needs a residual model as --init (train it with --residual) or a gain model");
  if (samples.empty()) throw InvalidArgument("train_through_pgs: no samples");
  Network& net = model.network();
  const Shape xs = net.input_shape(), ys = net.output_shape();
  for (std::size_t i = 0; i < samples.size(); ++i)
    require_shape(samples[i].features.shape(), xs, "train_through_pgs: sample " + std::to_string(i) + " features");
  using Clock = std::chrono::steady_clock;
  const auto t_start = Clock::now();
  const auto elapsed = [&] { return std::chrono::duration<double>(Clock::now() - t_start).count(); };

  Rng rng(def.seed);
  std::vector<TrainingSample> ids(samples.size());
  for (std::size_t i = 0; i < samples.size(); ++i) ids[i].simulation = samples[i].simulation;
  const std::vector<int> val = Trainer::pick_validation_simulations(ids, def.validation_fraction, rng);
  std::vector<std::size_t> tr, va;
  for (std::size_t i = 0; i < samples.size(); ++i)
    (std::find(val.begin(), val.end(), samples[i].simulation) != val.end() ? va : tr).push_back(i);
  if (tr.empty()) throw InvalidArgument("train_through_pgs: no training simulation left after the split");

  std::vector<PgsObjective> obj;
  obj.reserve(samples.size());
  for (const PgsSample& s : samples) obj.emplace_back(s, def.loss, def.unroll, def.floor, def.field_iterations);

  net.set_rng(&rng);
  Sgd opt(SgdDef{def.momentum, def.weight_decay});
  std::vector<ParamRef> params = net.parameters();
  const double s = model.grid().labels.scale;
  const std::size_t P = static_cast<std::size_t>(ys.h) * static_cast<std::size_t>(ys.w);
  const std::size_t fsz = samples[0].features.size(), osz = static_cast<std::size_t>(ys.c) * P;
  std::vector<PgsEpochReport> reports;
  std::vector<float> G(osz), dGdy(osz), dG(osz);
  bool stop = false;
  for (int e = 0; e < def.epochs && !stop; ++e) {
    const auto t0 = Clock::now();
    for (std::size_t i = tr.size(); i > 1; --i)
      std::swap(tr[i - 1], tr[static_cast<std::size_t>(rng.uniform_int(i))]);
    double sum = 0;
    std::size_t seen = 0;
    int clipped = 0, r_skipped = 0;
    double norm_sum = 0;
    int steps = 0;
    for (std::size_t b0 = 0; b0 < tr.size(); b0 += static_cast<std::size_t>(def.batch)) {
      if ((keep_going && !keep_going()) || (def.time_limit > 0 && elapsed() > def.time_limit)) {
        stop = true;
        break;
      }
      const std::size_t B = std::min(static_cast<std::size_t>(def.batch), tr.size() - b0);
      Tensor x(static_cast<int>(B), xs.c, xs.h, xs.w);
      for (std::size_t b = 0; b < B; ++b)
        std::copy_n(samples[tr[b0 + b]].features.data(), fsz, x.data() + b * fsz);
      model.input_stats.apply(x);
      const Tensor& y = net.forward(x, true);
      Tensor dy(static_cast<int>(B), ys.c, ys.h, ys.w);
      for (std::size_t b = 0; b < B; ++b) {
        expand_output(y.data() + b * osz, ys.c, P, model.output_stats, s, G.data(), dGdy.data());
        std::fill(dG.begin(), dG.end(), 0.0f);
        sum += obj[tr[b0 + b]].evaluate(G.data(), dG.data());
        ++seen;
        float* d = dy.data() + b * osz;
        for (std::size_t k = 0; k < osz; ++k) d[k] = dG[k] * dGdy[k] / static_cast<float>(B);
      }
      net.backward(dy);
      double sq = 0;
      for (const ParamRef& p : params)
        for (std::size_t k = 0; k < p.grad->size(); ++k) sq += double((*p.grad)[k]) * double((*p.grad)[k]);
      const double norm = std::sqrt(sq);
      if (!std::isfinite(norm)) {  // a non-finite gradient would poison the weights: skip the step
        ++r_skipped;
        continue;
      }
      norm_sum += norm;
      ++steps;
      if (def.clip > 0) {
        if (norm > def.clip) {
          const float f = static_cast<float>(def.clip / norm);
          for (const ParamRef& p : params)
            for (std::size_t k = 0; k < p.grad->size(); ++k) (*p.grad)[k] *= f;
          ++clipped;
        }
      }
      opt.step(params, def.learning_rate);
    }
    if (seen == 0) break;
    PgsEpochReport r;
    r.epoch = e;
    r.train_objective = sum / static_cast<double>(seen);
    std::tie(r.validation_objective, r.validation_improved) = pgs_objective_mean(model, samples, va, def);
    r.seconds = std::chrono::duration<double>(Clock::now() - t0).count();
    r.clipped = clipped;
    r.skipped = r_skipped;
    r.grad_norm = steps > 0 ? norm_sum / steps : 0.0;
    reports.push_back(r);
    if (on_epoch && !on_epoch(r)) break;
  }
  net.set_rng(nullptr);
  return reports;
}

}  // namespace dc
