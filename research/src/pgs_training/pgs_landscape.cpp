#include "dc/research/pgs_landscape.hpp"

#include <cmath>
#include <span>

#include "dc/core/error.hpp"

namespace dc {

void PgsLandscapeDef::validate() const {
  if (unrolls.empty()) throw ConfigError("--unroll: give at least one horizon");
  for (const int k : unrolls)
    if (k < 1) throw ConfigError("--unroll: every horizon must be >= 1");
  for (const double e : steps)
    if (!(e > 0) || !std::isfinite(e)) throw ConfigError("--steps: every step must be > 0");
  for (const double t : path)
    if (!std::isfinite(t)) throw ConfigError("--path: every entry must be finite");
  if (cgls_iterations < 1) throw ConfigError("--cgls-iterations must be >= 1");
  if (!(floor > 0) || !std::isfinite(floor)) throw ConfigError("--pgs-floor must be > 0");
}

namespace {

double dot(const std::vector<double>& a, const std::vector<double>& b) {
  double s = 0;
  for (std::size_t i = 0; i < a.size(); ++i) s += a[i] * b[i];
  return s;
}

double cosine(const std::vector<double>& a, const std::vector<double>& b) {
  const double na = std::sqrt(dot(a, a)), nb = std::sqrt(dot(b, b));
  return na > 0 && nb > 0 ? dot(a, b) / (na * nb) : 0.0;
}

/// J(G) of `obj` at G = a·dir (floats, as the trainer evaluates it).
double objective_at(PgsObjective& obj, const std::vector<double>& dir, double a, std::vector<float>& buf) {
  for (std::size_t i = 0; i < dir.size(); ++i) buf[i] = static_cast<float>(a * dir[i]);
  return obj.evaluate(buf.data(), nullptr);
}

}  // namespace

std::vector<PgsLandscapeLine> probe_pgs_landscape(const PgsSample& s, const PgsLandscapeDef& def) {
  def.validate();
  const std::size_t n = 2 * static_cast<std::size_t>(s.features.h()) * s.features.w();
  std::vector<double> field;
  if (s.lambda_star.size() == s.problem.rows()) {
    const std::vector<float> f = least_squares_correction_grid(s, def.cgls_iterations);
    field.assign(f.begin(), f.end());
  } else {
    field.assign(n, 0.0);
  }
  std::vector<float> zero(n, 0.0f), buf(n), gf(n);
  std::vector<double> first_dir, first_grad;
  std::vector<PgsLandscapeLine> lines;
  for (const int K : def.unrolls) {
    PgsObjective obj(s, def.loss, K, def.floor);
    std::fill(gf.begin(), gf.end(), 0.0f);
    (void)obj.evaluate(zero.data(), gf.data());
    const std::vector<double> g(gf.begin(), gf.end());
    PgsLandscapeLine L;
    L.unroll = K;
    L.grad_norm = std::sqrt(dot(g, g));
    const double rms = L.grad_norm / std::sqrt(static_cast<double>(n));
    std::vector<double> d(n, 0.0);
    if (rms > 0)
      for (std::size_t i = 0; i < n; ++i) d[i] = -g[i] / rms;
    L.slope = dot(g, d);
    if (first_dir.empty()) {
      first_dir = d;
      first_grad = g;
    }
    L.cos_to_first = cosine(g, first_grad);
    L.cos_to_field = -cosine(g, field);
    for (const double e : def.steps) {
      L.along_own.push_back(objective_at(obj, d, e, buf));
      L.along_first.push_back(objective_at(obj, first_dir, e, buf));
    }
    for (const double t : def.path) L.along_field.push_back(objective_at(obj, field, t, buf));
    lines.push_back(std::move(L));
  }
  return lines;
}

}  // namespace dc
