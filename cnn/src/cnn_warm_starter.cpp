#include "dc/cnn/cnn_warm_starter.hpp"

#include <omp.h>

#include <chrono>
#include <algorithm>
#include <cmath>

#include "dc/cnn/cnn_starter_options.hpp"
#include "dc/cnn/contact_readback.hpp"
#include "dc/core/error.hpp"
#include "dc/learning/model_file.hpp"
#include "dc/sph/sph_splat.hpp"
#include "dc/warmstart/sph_warm_starter.hpp"

namespace dc {

namespace {

using Clock = std::chrono::steady_clock;
double ms_since(Clock::time_point t0) { return std::chrono::duration<double, std::milli>(Clock::now() - t0).count(); }

/// Sets the calling thread's OpenMP team size for its next parallel regions and restores
/// the previous value on exit (an ICV of this thread, not process state).
class OmpThreads {
 public:
  explicit OmpThreads(int n) : previous_(omp_get_max_threads()) {
    if (n > 0) omp_set_num_threads(n);
  }
  ~OmpThreads() { omp_set_num_threads(previous_); }
  OmpThreads(const OmpThreads&) = delete;
  OmpThreads& operator=(const OmpThreads&) = delete;

 private:
  int previous_;
};

/// (λ_prev,n, λ_prev,t) of each current contact of w by key (0, 0 for a new contact).
std::vector<double> previous_pairs(const World& w) {
  const auto& cur = w.contacts();
  const auto& prev = w.previous_contacts();
  const std::vector<int> match = match_contacts_by_key(prev, cur);
  std::vector<double> out(2 * cur.size(), 0.0);
  for (std::size_t c = 0; c < cur.size(); ++c) {
    if (match[c] < 0) continue;
    out[2 * c] = prev[static_cast<std::size_t>(match[c])].lambda_n;
    out[2 * c + 1] = prev[static_cast<std::size_t>(match[c])].lambda_t;
  }
  return out;
}

/// Largest force [N] the network may put on each contact row (a guess of an absolute model, a
/// correction of a residual one): Λ_i = W + max(0, −b_i) / A_ii, where W = Σ_k m_k |g| is the
/// weight of every dynamic body (the most a static load path can carry) and −b_i / A_ii is the
/// force that, acting alone, stops row i's approach velocity (b holds the free velocity with
/// the Baumgarte and restitution targets; A_ii = Δt Σ_j J_ij² M⁻¹_jj). The network's S·sinh
/// head turns an extrapolated output into an exponentially large one, far above any λ*, and
/// into inf once the state leaves its training range; with few PGS sweeps such a guess injects
/// energy that the sweeps cannot take out, and the run diverges (docs/learning.md "Bounded
/// guesses"). The cap bounds the guess, not the solution: PGS still reaches any larger λ*.
Eigen::VectorXd force_caps(const World& w) {
  const BodyState& bodies = w.bodies();
  double weight = 0;
  for (std::size_t k = 0; k < bodies.size(); ++k) weight += bodies.mass[k];
  weight *= length(w.def().world.gravity);
  const LcpProblem& p = w.problem();
  Eigen::VectorXd cap = Eigen::VectorXd::Constant(p.rows(), weight);
  for (int i = 0; i < p.rows(); ++i) {
    double aii = 0;
    if (p.has_jacobian()) {
      for (SparseRowMatrix::InnerIterator it(p.J, i); it; ++it) aii += it.value() * it.value() * p.inv_mass[it.col()];
      aii *= p.dt;
    } else {
      aii = p.A.coeff(i, i);
    }
    if (aii > 0 && p.b[i] < 0) cap[i] += -p.b[i] / aii;
  }
  return cap;
}

/// Clamps every entry of the network's guess or correction to ±force_caps(w); a NaN (an
/// overflow inside the network) becomes 0: no correction, builtin's value.
void cap_network_forces(const World& w, Eigen::VectorXd& v) {
  const Eigen::VectorXd cap = force_caps(w);
  for (Eigen::Index i = 0; i < v.size(); ++i) v[i] = std::isnan(v[i]) ? 0.0 : std::clamp(v[i], -cap[i], cap[i]);
}

}  // namespace

Eigen::VectorXd CnnWarmStarter::read_back_grid(const World& w, const SphGrid* weights,
                                               std::span<const BilinearStencil> stencils) {
  if (model_.grid().labels.kind != LabelKind::Gain && weights != nullptr) {
    // SphTransfer::gather without its splat of S: the same gather_shepard on the same S, with
    // the contacts' stencils when stencil_nodes() has them (the same stencils).
    const std::size_t n = w.contacts().size();
    readback_.resize(2 * n);
    unsupported_.resize(n);
    const double min_weight = transfer_->def().min_weight_ratio * transfer_->kernel().peak();
    if (stencils.size() == n) {
      gather_shepard(grid_, *weights, stencils, readback_, unsupported_, min_weight);
    } else {
      points_.clear();
      for (const Contact& c : w.contacts()) points_.push_back(c.point);
      gather_shepard(grid_, *weights, points_, readback_, unsupported_, min_weight);
    }
    return w.constraints().scatter(readback_);
  }
  points_.clear();
  for (const Contact& c : w.contacts()) points_.push_back(c.point);
  if (model_.grid().labels.kind != LabelKind::Gain) return w.constraints().scatter(transfer_->gather(grid_, points_));
  // Gain model: δ = λp·ĝ, the load-weighted read-back of the gain field (contact_readback.hpp),
  // the map it was trained through.
  const ContactReadback rb = ContactReadback::gain(*transfer_, points_, previous_pairs(w));
  std::vector<double> v(2 * points_.size());
  rb.forward(grid_.data().data(), v);
  return w.constraints().scatter(v);
}

CnnWarmStarter::CnnWarmStarter(Model model, std::string name, bool hybrid, int inference_threads)
    : model_(std::move(model)), name_(std::move(name)), hybrid_(hybrid), threads_(inference_threads) {
  if (model_.grid().label_channels != label_channel_names())
    throw ConfigError(name_ + ": the model's label channels are not lambda_n, lambda_t");
}

std::unique_ptr<CnnWarmStarter> CnnWarmStarter::load(const std::filesystem::path& path, std::string name, bool hybrid,
                                                     int inference_threads) {
  if (!std::filesystem::exists(path))
    throw IoError(name + ": model file " + path.string() +
                  " does not exist (train one with 'make model' or pass cnn:PATH / --model)");
  return std::make_unique<CnnWarmStarter>(load_model(path), std::move(name), hybrid, inference_threads);
}

void CnnWarmStarter::prepare(const World& world) {
  const double W = world.def().world.width, H = world.def().world.height;
  if (builder_ && W == box_w_ && H == box_h_) {
    if (!plan_ || !plan_->built_for(model_.network())) plan_.emplace(model_.network(), model_.input_stats);
    return;
  }
  plan_.reset();
  const ModelGrid& g = model_.grid();
  // The model's feature image (kernel, d, h, channels) on this scene's box: the same node
  // spacing and kernel support, so a node sees the same physical neighbourhood as in
  // training, and the fully convolutional network runs on this grid's nx × ny with the
  // trained weights (Network::set_input_size; the model's own grid leaves it untouched).
  FeatureImageDef def = g.image;
  def.sph.grid.width = W;
  def.sph.grid.height = H;
  builder_.emplace(def);
  const int nx = builder_->nx(), ny = builder_->ny();
  try {
    model_.network().set_input_size(ny, nx);
  } catch (const ConfigError& e) {
    builder_.reset();
    throw ConfigError(name_ + ": the model (trained on a " + std::to_string(g.nx()) + " x " + std::to_string(g.ny()) +
                      " grid) cannot run on this scene's " + std::to_string(nx) + " x " + std::to_string(ny) +
                      " grid: " + e.what());
  }
  SphTransferDef t = def.sph;
  t.grid.channels = FeatureImageBuilder::kLabelChannels;
  t.normalisation = SphNormalisation::Shepard;
  transfer_.emplace(t);
  grid_ = SphGrid(t.grid);
  features_ = Tensor(1, builder_->feature_channels(), ny, nx);
  box_w_ = W;
  box_h_ = H;
  plan_.emplace(model_.network(), model_.input_stats);
}

InferencePlan& CnnWarmStarter::inference_plan(const World& world) {
  prepare(world);
  return *plan_;
}

Eigen::VectorXd CnnWarmStarter::guess_from_labels(const World& w, const Tensor& labels, bool project) {
  prepare(w);
  require_shape(labels.shape(), Shape{1, FeatureImageBuilder::kLabelChannels, grid_.ny(), grid_.nx()},
                name_ + ": label grid");
  Eigen::VectorXd out = Eigen::VectorXd::Zero(w.problem().rows());
  const auto& contacts = w.contacts();
  if (contacts.empty()) return out;
  // Same layout (c·ny + j)·nx + i on both sides: a straight float → double copy.
  const std::span<double> dst = grid_.data();
  for (std::size_t i = 0; i < dst.size(); ++i) dst[i] = labels[i];
  out = read_back_grid(w);
  if (project) project_feasible(w.problem(), out);
  return out;
}

std::span<const int> CnnWarmStarter::stencil_nodes(const World& w) {
  prepare(w);
  const int nx = grid_.nx();
  const std::size_t P = static_cast<std::size_t>(nx) * static_cast<std::size_t>(grid_.ny());
  if (stamp_.size() != P) stamp_.assign(P, 0);
  if (++call_ == 0) {  // wrapped: forget all marks
    std::fill(stamp_.begin(), stamp_.end(), 0u);
    call_ = 1;
  }
  nodes_.clear();
  stencils_.clear();
  for (const Contact& c : w.contacts()) {
    const BilinearStencil st = grid_.stencil(c.point);
    stencils_.push_back(st);
    const int is[2] = {st.i0, st.i1}, js[2] = {st.j0, st.j1};
    for (const int j : js)
      for (const int i : is) {
        const int node = j * nx + i;
        if (stamp_[static_cast<std::size_t>(node)] == call_) continue;
        stamp_[static_cast<std::size_t>(node)] = call_;
        nodes_.push_back(node);
      }
  }
  return nodes_;
}

Eigen::VectorXd CnnWarmStarter::guess_from_output(const World& w, const Tensor& y, bool project,
                                                  const SphGrid* contact_weights) {
  prepare(w);
  const int nx = grid_.nx(), ny = grid_.ny();
  require_shape(y.shape(), Shape{1, FeatureImageBuilder::kLabelChannels, ny, nx}, name_ + ": network output");
  Eigen::VectorXd out = Eigen::VectorXd::Zero(w.problem().rows());
  if (w.contacts().empty()) return out;
  out = read_back_output(w, y, stencil_nodes(w), contact_weights);
  if (project) project_feasible(w.problem(), out);
  return out;
}

Eigen::VectorXd CnnWarmStarter::read_back_output(const World& w, const Tensor& y, std::span<const int> nodes,
                                                 const SphGrid* contact_weights) {
  // The Shepard read-back reads only the four nodes of each point's bilinear stencil, so only
  // those are de-standardised and expanded (s·sinh), a small share of the outputs. The other nodes of grid_ keep stale values that nothing reads.
  // Gathered into one buffer per channel so that the expansion runs vectorised
  // (Model::label_values: label_value bit for bit).
  const std::size_t P = static_cast<std::size_t>(grid_.nx()) * static_cast<std::size_t>(grid_.ny());
  const std::span<double> dst = grid_.data();
  node_values_.resize(nodes.size());
  for (int ch = 0; ch < FeatureImageBuilder::kLabelChannels; ++ch) {
    const float* src = y.data() + static_cast<std::size_t>(ch) * P;
    double* to = dst.data() + static_cast<std::size_t>(ch) * P;
    for (std::size_t n = 0; n < nodes.size(); ++n) node_values_[n] = src[nodes[n]];
    model_.label_values(ch, node_values_);
    for (std::size_t n = 0; n < nodes.size(); ++n) to[nodes[n]] = node_values_[n];
  }
  return read_back_grid(w, contact_weights, stencils_);
}

Eigen::VectorXd CnnWarmStarter::initial_guess(const StepView& view) {
  const World& w = view.world;
  last_ = {};
  const auto& cur = w.contacts();
  if (cur.empty()) return Eigen::VectorXd::Zero(w.problem().rows());

  // Which contacts persist from the previous step (index into previous_contacts(), −1 new):
  // needed by the hybrid policy and by a residual model (λ⁰ = λ_prev + correction).
  const auto& prev = w.previous_contacts();
  const bool residual = is_corrective(model_.grid().labels.kind);  // λ⁰ = λ_prev + a correction
  std::vector<int> prev_of;
  if (hybrid_ || residual) prev_of = match_contacts_by_key(prev, cur);
  const bool any_new = !hybrid_ || std::find(prev_of.begin(), prev_of.end(), -1) != prev_of.end();

  Eigen::VectorXd out = Eigen::VectorXd::Zero(w.problem().rows());
  if (any_new) {
    auto t0 = Clock::now();
    prepare(w);
    try {  // the key match once per step: the builder's lambda_prev channels reuse prev_of
      builder_->features(w.bodies(), cur, prev, &w.problem(), std::span<float>(features_.data(), features_.size()),
                         prev_of);
    } catch (const InvalidArgument& e) {  // a non-finite state: say which starter met it, and where
      throw InvalidArgument(name_ + ": step " + std::to_string(w.step_index() + 1) + ": " + e.what());
    }
    last_.features_ms = ms_since(t0);
    t0 = Clock::now();
    // The stencil nodes (and stencils) once per step: the network's pixels and the read-back's.
    const std::span<const int> nodes = stencil_nodes(w);
    const Tensor* raw = nullptr;
    {
      const OmpThreads scope(threads_);
      // The builder's rows outside which the features are +0: the plan need not scan for them.
      const auto [lo, hi] = builder_->nonzero_rows();
      raw = &plan_->run(features_, nodes, InferencePlan::InputRows{lo, hi});
    }
    last_.inference_ms = ms_since(t0);
    t0 = Clock::now();
    out = read_back_output(w, *raw, nodes, builder_->contact_weights());
    cap_network_forces(w, out);
    if (!residual) project_feasible(w.problem(), out);
    if (residual) {
      // Soft threshold: corrections within the network's noise level leave builtin alone.
      apply_deadzone(std::span<double>(out.data(), static_cast<std::size_t>(out.size())), model_.grid().labels.deadzone);
      for (std::size_t c = 0; c < cur.size(); ++c) {
        if (prev_of[c] < 0) continue;
        const Contact& p = prev[static_cast<std::size_t>(prev_of[c])];
        const int k = static_cast<int>(c);
        const ContactConstraints& cons = w.constraints();
        cons.put(k, cons.lambda_n(out, k) + p.lambda_n, cons.lambda_t(out, k) + p.lambda_t, out);
      }
      project_feasible(w.problem(), out);
    }
    last_.gather_ms = ms_since(t0);
    last_.calls = 1;
  }
  if (hybrid_) {
    for (std::size_t c = 0; c < cur.size(); ++c) {
      if (prev_of[c] < 0) continue;
      const Contact& p = prev[static_cast<std::size_t>(prev_of[c])];
      w.constraints().put(static_cast<int>(c), p.lambda_n, p.lambda_t, out);
    }
    project_feasible(w.problem(), out);
  }
  total_.features_ms += last_.features_ms;
  total_.inference_ms += last_.inference_ms;
  total_.gather_ms += last_.gather_ms;
  total_.calls += last_.calls;
  return out;
}

void add_cnn_warm_starters(WarmStarterRegistry& registry, std::filesystem::path default_model) {
  const auto factory = [default_model](const WarmStartSpec& spec, const WarmStartEnv& env) -> std::unique_ptr<WarmStarter> {
    const CnnStarterOptions o = parse_cnn_options(spec);
    return CnnWarmStarter::load(cnn_model_path(o, env, default_model), spec.full(), o.hybrid);
  };
  registry.add("cnn",
               "learned: body state (+ builtin for a residual model) -> feature grid -> CNN -> label grid -> "
               "back at the contacts (+ builtin); cnn:MODEL.h5 (default: --model or the shipped models/default.h5)",
               factory);
  registry.add("cnn-hybrid", "builtin for persistent contacts, cnn for new ones (network skipped when none is new); "
                             "cnn-hybrid:MODEL.h5",
               factory);
}

}  // namespace dc
