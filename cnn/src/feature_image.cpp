#include "dc/cnn/feature_image.hpp"

#include <algorithm>
#include <cmath>
#include <initializer_list>
#include <sstream>

#include "dc/core/error.hpp"
#include "dc/sph/sph_splat.hpp"

namespace dc {

namespace {

SphTransferDef normalised_label_def(SphTransferDef d) {
  d.grid.channels = FeatureImageBuilder::kLabelChannels;
  d.normalisation = SphNormalisation::Shepard;
  return d;
}

SphGridDef with_channels(SphGridDef g, int channels) {
  g.channels = channels;
  return g;
}

bool uses_contact_fields(const std::vector<FeatureChannel>& cs) {
  return std::any_of(cs.begin(), cs.end(), [](FeatureChannel c) {
    return c == FeatureChannel::ContactDensity || c == FeatureChannel::Nx || c == FeatureChannel::Ny;
  });
}

bool uses_contact_values(const std::vector<FeatureChannel>& cs) {
  return std::any_of(cs.begin(), cs.end(), [](FeatureChannel c) {
    return c == FeatureChannel::LambdaPrevN || c == FeatureChannel::LambdaPrevT || c == FeatureChannel::VrelN ||
           c == FeatureChannel::VrelT || c == FeatureChannel::Gap;
  });
}

bool uses_shape_fields(const std::vector<FeatureChannel>& cs) {
  return std::any_of(cs.begin(), cs.end(), [](FeatureChannel c) {
    return c == FeatureChannel::Coverage || c == FeatureChannel::OrientC || c == FeatureChannel::OrientS;
  });
}

/// Velocity of the material point p of body k [m/s]: v + ω × (p − x); 0 for a wall (k < 0).
Vec2 point_velocity(const BodyState& s, int k, Vec2 p) {
  if (k < 0) return {0.0, 0.0};
  const auto i = static_cast<std::size_t>(k);
  const Vec2 r = p - s.position[i];
  return s.velocity[i] + Vec2{-s.omega[i] * r.y, s.omega[i] * r.x};
}

/// InvalidArgument naming the first non-finite value of a splat's `values` (row-major, one row
/// per point of `kind`, one column per name) and the state's largest body speed, which tells a
/// diverged simulation (speeds of 1e100 m/s and more) from a bad input. Checked here rather
/// than in the splat so that the message says which feature it is.
void require_finite_features(std::span<const double> values, std::initializer_list<const char*> names,
                             const char* kind, const BodyState& bodies) {
  const std::size_t C = names.size();
  for (std::size_t k = 0; k < values.size(); ++k) {
    if (std::isfinite(values[k])) continue;
    double fastest = 0;
    for (const Vec2& v : bodies.velocity) fastest = std::max(fastest, length(v));
    std::ostringstream os;
    os << "feature image: " << kind << " " << k / C << ": " << names.begin()[k % C] << " = " << values[k]
       << " is not finite (largest body speed " << fastest << " m/s"
       << (std::isfinite(fastest) && fastest < 1e100 ? ")" : ": the simulation has diverged)");
    throw InvalidArgument(os.str());
  }
}

}  // namespace

FeatureImageBuilder::FeatureImageBuilder(FeatureImageDef def)
    : def_((def.validate(), std::move(def))),
      kernel_(def_.sph.kernel, def_.sph.support),
      label_transfer_(normalised_label_def(def_.sph)) {
  def_.sph = normalised_label_def(def_.sph);
  body_grid_ = SphGrid(with_channels(def_.sph.grid, 4));
  body_weight_ = SphGrid(with_channels(def_.sph.grid, 1));
  if (uses_contact_fields(def_.channels)) {
    contact_grid_ = SphGrid(with_channels(def_.sph.grid, 2));
    contact_weight_ = SphGrid(with_channels(def_.sph.grid, 1));
  }
  if (uses_contact_values(def_.channels)) contact_values_ = SphGrid(with_channels(def_.sph.grid, 5));
  if (needs_lcp_problem(def_.channels)) w_prev_grid_ = SphGrid(with_channels(def_.sph.grid, 2));
  if (uses_shape_fields(def_.channels)) shape_grid_ = SphGrid(with_channels(def_.sph.grid, 3));
  nx_ = body_grid_.nx();
  ny_ = body_grid_.ny();
}

void FeatureImageBuilder::features(const BodyState& bodies, std::span<const Contact> contacts,
                                   std::span<const Contact> previous, const LcpProblem* problem,
                                   std::span<float> out, std::span<const int> match) {
  if (out.size() != feature_size())
    throw InvalidArgument("FeatureImageBuilder::features: output holds " + std::to_string(out.size()) +
                          " floats, expected " + std::to_string(feature_size()));
  if (!match.empty() && match.size() != contacts.size())
    throw InvalidArgument("FeatureImageBuilder::features: " + std::to_string(match.size()) + " key matches for " +
                          std::to_string(contacts.size()) + " contacts");
  rows_lo_ = 0;
  rows_hi_ = nx_ > 0 ? ny_ - 1 : -1;  // until this call's rows are known (a throw leaves them all)
  // The key match of the contacts with the previous step's, once (lambda_prev and w_prev).
  std::vector<int> own_match;
  bool own_matched = false;
  const auto matched = [&]() -> std::span<const int> {
    if (!match.empty()) return match;
    if (!own_matched) own_match = match_contacts_by_key(previous, contacts);
    own_matched = true;
    return own_match;
  };
  // Every grid is zero outside the rows [dirty_lo_, dirty_hi_]: only those are cleared before
  // a splat (the pile fills part of the box), and the rows this call writes are collected.
  SplatRows rows{dirty_lo_, dirty_hi_, ny_, -1};
  splat_bodies(bodies, rows);
  const bool density_with_values = splat_contact_fields(bodies, contacts, rows);
  if (uses_contact_values(def_.channels)) {
    const auto uses = [&](FeatureChannel c) {
      return std::find(def_.channels.begin(), def_.channels.end(), c) != def_.channels.end();
    };
    const bool want_prev = uses(FeatureChannel::LambdaPrevN) || uses(FeatureChannel::LambdaPrevT);
    splat_contact_values(bodies, contacts, previous, want_prev ? matched() : std::span<const int>(),
                         density_with_values, rows);
  }
  if (needs_lcp_problem(def_.channels)) {
    if (problem == nullptr)
      throw InvalidArgument("FeatureImageBuilder::features: channels w_prev_n/w_prev_t need the step's LcpProblem");
    if (static_cast<std::size_t>(problem->constraints.size()) != contacts.size())
      throw InvalidArgument("FeatureImageBuilder::features: the problem has " +
                            std::to_string(problem->constraints.size()) + " contacts, the step " +
                            std::to_string(contacts.size()));
    splat_w_prev(bodies, contacts, previous, *problem, matched(), rows);
  }
  if (uses_shape_fields(def_.channels)) splat_shapes(bodies, rows);

  // Every grid is now zero outside rows [lo, hi].
  dirty_lo_ = rows.lo;
  dirty_hi_ = rows.hi;
  rows_lo_ = rows.lo;
  rows_hi_ = rows.hi;
  write_channels(out, rows.lo, rows.hi);
}

void FeatureImageBuilder::mark_written(int row_lo, int row_hi, SplatRows& rows) {
  if (row_lo > row_hi) return;
  rows.lo = std::min(rows.lo, row_lo);
  rows.hi = std::max(rows.hi, row_hi);
  // Kept true at every point (a throw may leave this call's grids half done).
  dirty_lo_ = dirty_lo_ > dirty_hi_ ? row_lo : std::min(dirty_lo_, row_lo);
  dirty_hi_ = std::max(dirty_hi_, row_hi);
}

void FeatureImageBuilder::splat_points(SphGrid& grid, SphGrid* weights, SplatRows& rows) {
  const SplatStats st = splat_to_grid_rows(kernel_, points_, values_, grid, weights, rows.clear_lo, rows.clear_hi);
  mark_written(st.row_lo, st.row_hi, rows);
}

// Bodies: one splat of (m, vx, vy, ω) at the centres plus the weight field S = Σ W.
void FeatureImageBuilder::splat_bodies(const BodyState& bodies, SplatRows& rows) {
  const std::size_t n = bodies.size();
  points_.assign(bodies.position.begin(), bodies.position.end());
  values_.resize(4 * n);
  for (std::size_t k = 0; k < n; ++k) {
    values_[4 * k + 0] = bodies.mass[k];
    values_[4 * k + 1] = bodies.velocity[k].x;
    values_[4 * k + 2] = bodies.velocity[k].y;
    values_[4 * k + 3] = bodies.omega[k];
  }
  require_finite_features(values_, {"mass", "vx", "vy", "omega"}, "body", bodies);
  splat_points(body_grid_, &body_weight_, rows);
}

// Contacts: (nx, ny) at the points plus their weight field (the contact density).
bool FeatureImageBuilder::splat_contact_fields(const BodyState& bodies, std::span<const Contact> contacts,
                                               SplatRows& rows) {
  const bool contact_fields = uses_contact_fields(def_.channels);
  has_contact_weights_ = false;
  if (contact_fields) {
    const bool normals = std::find(def_.channels.begin(), def_.channels.end(), FeatureChannel::Nx) != def_.channels.end() ||
                         std::find(def_.channels.begin(), def_.channels.end(), FeatureChannel::Ny) != def_.channels.end();
    points_.clear();
    values_.clear();
    for (const Contact& c : contacts) {
      points_.push_back(c.point);
      values_.push_back(c.normal.x);
      values_.push_back(c.normal.y);
    }
    // The contact density alone (the residual model's channels) needs no normal field; with
    // the per-contact values it comes out of their splat (same points, same order: the same S).
    require_finite_features(values_, {"nx", "ny"}, "contact", bodies);
    if (normals) {
      splat_points(contact_grid_, &contact_weight_, rows);
      has_contact_weights_ = true;
    } else if (!uses_contact_values(def_.channels)) {
      const SplatStats st = splat_weights(kernel_, points_, contact_weight_);
      mark_written(st.row_lo, st.row_hi, rows);
      has_contact_weights_ = true;
    }
  }
  return contact_fields && !has_contact_weights_;
}

// Per-contact values (numerators, like the labels): builtin λ, relative velocity, gap. `match`
// is empty when no lambda_prev channel is listed (λ_prev is then 0).
void FeatureImageBuilder::splat_contact_values(const BodyState& bodies, std::span<const Contact> contacts,
                                               std::span<const Contact> previous, std::span<const int> match,
                                               bool density_with_values, SplatRows& rows) {
  const bool want_prev = !match.empty();
  points_.clear();
  values_.clear();
  for (std::size_t c = 0; c < contacts.size(); ++c) {
    const Contact& ct = contacts[c];
    const Contact* p = want_prev && match[c] >= 0 ? &previous[static_cast<std::size_t>(match[c])] : nullptr;
    const Vec2 u = point_velocity(bodies, ct.body_b, ct.point) - point_velocity(bodies, ct.body_a, ct.point);
    points_.push_back(ct.point);
    values_.push_back(p ? p->lambda_n : 0.0);
    values_.push_back(p ? p->lambda_t : 0.0);
    values_.push_back(dot(u, ct.normal));
    values_.push_back(dot(u, perp(ct.normal)));
    values_.push_back(ct.gap);
  }
  require_finite_features(values_, {"lambda_prev_n", "lambda_prev_t", "vrel_n", "vrel_t", "gap"}, "contact", bodies);
  splat_points(contact_values_, density_with_values ? &contact_weight_ : nullptr, rows);
  has_contact_weights_ = uses_contact_fields(def_.channels);
}

// The builtin guess's LCP velocity w = A λ_prev + b per contact (matrix-free when the problem
// has J): the violation that the correction λ* − λ_prev has to undo.
void FeatureImageBuilder::splat_w_prev(const BodyState& bodies, std::span<const Contact> contacts,
                                       std::span<const Contact> previous, const LcpProblem& problem,
                                       std::span<const int> match, SplatRows& rows) {
  const ContactConstraints& cons = problem.constraints;
  Eigen::VectorXd lambda = Eigen::VectorXd::Zero(problem.rows());
  for (std::size_t c = 0; c < contacts.size(); ++c) {
    if (match[c] < 0) continue;
    const Contact& p = previous[static_cast<std::size_t>(match[c])];
    cons.put(static_cast<int>(c), p.lambda_n, p.lambda_t, lambda);
  }
  const Eigen::VectorXd w = lcp_velocity(problem, lambda);
  points_.clear();
  values_.clear();
  for (std::size_t c = 0; c < contacts.size(); ++c) {
    points_.push_back(contacts[c].point);
    values_.push_back(cons.lambda_n(w, static_cast<int>(c)));
    values_.push_back(cons.lambda_t(w, static_cast<int>(c)));
  }
  require_finite_features(values_, {"w_prev_n", "w_prev_t"}, "contact", bodies);
  splat_points(w_prev_grid_, nullptr, rows);
}

// Shapes: area samples of every body with (a, a Q_x, a Q_y); coverage = Σ W a is channel 0.
void FeatureImageBuilder::splat_shapes(const BodyState& bodies, SplatRows& rows) {
  // Sample spacing h/2: the kernels of neighbouring samples overlap (a smooth plateau).
  const double spacing = 0.5 * def_.sph.support;
  points_.clear();
  values_.clear();
  for (std::size_t k = 0; k < bodies.size(); ++k) {
    samples_.clear();
    append_area_samples(bodies, k, spacing, samples_);
    const bool round = bodies.shapes.empty() || bodies.shapes.kind[k] == ShapeKind::Circle;
    // A disc's samples need no rotation (and its Q is 0): no cos/sin for circle-only scenes.
    const double c = round ? 1.0 : std::cos(bodies.angle[k]), s = round ? 0.0 : std::sin(bodies.angle[k]);
    const Vec2 q = rotate_nematic(body_frame_nematic(bodies, k), c, s);
    const Vec2 x = bodies.position[k];
    for (const AreaSample& a : samples_) {
      points_.push_back(x + Vec2{c * a.point.x - s * a.point.y, s * a.point.x + c * a.point.y});
      values_.push_back(a.area);
      values_.push_back(a.area * q.x);
      values_.push_back(a.area * q.y);
    }
  }
  splat_points(shape_grid_, nullptr, rows);
}

// The channels there are +0 outside rows [lo, hi] (0 and the Shepard quotient 0/1 alike), so
// only the nodes [p0, p1) of those rows are converted.
void FeatureImageBuilder::write_channels(std::span<float> out, int lo, int hi) {
  const std::size_t P = plane();
  const std::size_t p0 = lo <= hi ? static_cast<std::size_t>(lo) * nx_ : 0;
  const std::size_t p1 = lo <= hi ? static_cast<std::size_t>(hi + 1) * nx_ : 0;
  ratio_.resize(P);
  const std::span<const double> S = body_weight_.channel(0);
  for (std::size_t ci = 0; ci < def_.channels.size(); ++ci) {
    float* dst = out.data() + ci * P;
    std::fill(dst, dst + p0, 0.0f);
    std::fill(dst + p1, dst + P, 0.0f);
    // Shepard average of grid channel `g` over the weight field `w`: 0 where no support.
    // Written as two branch-free loops (0/1 where w ≤ 0, then the float conversion), which
    // GCC vectorises; the same quotients as num/w where w > 0 and +0 elsewhere.
    auto shepard = [&](const SphGrid& grid, int g, std::span<const double> w) {
      const double* num = grid.channel(g).data();
      const double* den = w.data();
      double* q = ratio_.data();
      for (std::size_t p = p0; p < p1; ++p) {
        const double n = num[p], d = den[p];
        q[p] = (d > 0 ? n : 0.0) / (d > 0 ? d : 1.0);
      }
      for (std::size_t p = p0; p < p1; ++p) dst[p] = static_cast<float>(q[p]);
    };
    auto copy = [&](std::span<const double> src) {
      for (std::size_t p = p0; p < p1; ++p) dst[p] = static_cast<float>(src[p]);
    };
    switch (def_.channels[ci]) {
      case FeatureChannel::Mass: copy(body_grid_.channel(0)); break;
      case FeatureChannel::Vx: shepard(body_grid_, 1, S); break;
      case FeatureChannel::Vy: shepard(body_grid_, 2, S); break;
      case FeatureChannel::Omega: shepard(body_grid_, 3, S); break;
      case FeatureChannel::ContactDensity: copy(contact_weight_.channel(0)); break;
      case FeatureChannel::Nx: shepard(contact_grid_, 0, contact_weight_.channel(0)); break;
      case FeatureChannel::Ny: shepard(contact_grid_, 1, contact_weight_.channel(0)); break;
      case FeatureChannel::LambdaPrevN: copy(contact_values_.channel(0)); break;
      case FeatureChannel::LambdaPrevT: copy(contact_values_.channel(1)); break;
      case FeatureChannel::VrelN: copy(contact_values_.channel(2)); break;
      case FeatureChannel::VrelT: copy(contact_values_.channel(3)); break;
      case FeatureChannel::Gap: copy(contact_values_.channel(4)); break;
      case FeatureChannel::Coverage: copy(shape_grid_.channel(0)); break;
      case FeatureChannel::OrientC: shepard(shape_grid_, 1, shape_grid_.channel(0)); break;
      case FeatureChannel::OrientS: shepard(shape_grid_, 2, shape_grid_.channel(0)); break;
      case FeatureChannel::WPrevN: copy(w_prev_grid_.channel(0)); break;
      case FeatureChannel::WPrevT: copy(w_prev_grid_.channel(1)); break;
    }
  }
}

void FeatureImageBuilder::labels(std::span<const Contact> contacts, std::span<const double> lambda,
                                 std::span<float> out) {
  if (out.size() != label_size())
    throw InvalidArgument("FeatureImageBuilder::labels: output holds " + std::to_string(out.size()) +
                          " floats, expected " + std::to_string(label_size()));
  if (lambda.size() != 2 * contacts.size())
    throw InvalidArgument("FeatureImageBuilder::labels: " + std::to_string(lambda.size()) +
                          " lambda values for " + std::to_string(contacts.size()) + " contacts (expected 2 each)");
  points_.clear();
  for (const Contact& c : contacts) points_.push_back(c.point);
  // SphTransfer::splat in Shepard mode: G = Σ W λ (the numerator), exactly the sph starter's grid.
  const SphGrid& g = label_transfer_.splat(points_, lambda);
  const std::span<const double> src = g.data();
  for (std::size_t p = 0; p < src.size(); ++p) out[p] = static_cast<float>(src[p]);
}

}  // namespace dc
