#pragma once
// The learned warm starters (docs/design.md §4–5; docs/learning.md "The cnn warm starter"):
//   cnn         feature image of this step (the model's grid and channels, on the scene's box)
//               → Model::predict → label grid → Shepard read-back at the contact points
//               (SphTransfer::gather, the `sph` starter's read-back) → projected into the
//               bounds. A residual model (labels.hpp) gives λ⁰ = λ_prev (by key, 0 if new) +
//               the read-back soft-thresholded by its correction_deadzone τ, projected.
//   cnn-hybrid  builtin (the previous step's λ by key) for persistent contacts, cnn for the
//               new ones; steps without new contacts skip the network. A non-oracle starter.
// Model: `cnn:PATH`, else WarmStartEnv::model_path, else the default given to
// add_cnn_warm_starters; a missing or unreadable model is an IoError when the starter is made.
// A fully convolutional network is re-targeted to the scene's node count with the same
// weights (Network::set_input_size); one that cannot is refused with a ConfigError.
#include <cstdint>
#include <filesystem>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "dc/cnn/feature_image.hpp"
#include "dc/learning/inference_plan.hpp"
#include "dc/learning/model.hpp"
#include "dc/sph/sph_transfer.hpp"
#include "dc/warmstart/warm_starter.hpp"

namespace dc {

/// Milliseconds spent in the parts of initial_guess().
struct CnnTiming {
  double features_ms = 0;   ///< feature image from bodies and contacts
  double inference_ms = 0;  ///< the network (inference plan: standardisation fused in) at the stencil nodes
  double gather_ms = 0;     ///< Shepard read-back at the contacts, projection
  long calls = 0;           ///< initial_guess() calls (total_timing) that ran the network
};

class CnnWarmStarter final : public WarmStarter {
 public:
  /// `name` is the full starter name ("cnn", "cnn:PATH", "cnn-hybrid"). `inference_threads`
  /// bounds the OpenMP threads of predict() (set around the call and restored): a batch-1
  /// pass is a chain of short fork–joins, which one thread runs fastest on a loaded machine
  /// (docs/learning.md "Speed").
  CnnWarmStarter(Model model, std::string name, bool hybrid, int inference_threads = 1);
  /// load_model(path) (IoError with the path) then the constructor above.
  static std::unique_ptr<CnnWarmStarter> load(const std::filesystem::path& path, std::string name, bool hybrid,
                                              int inference_threads = 1);

  [[nodiscard]] std::string name() const override { return name_; }
  /// λ⁰ in the problem's row order, finite, projected into the bounds. Throws ConfigError
  /// when the network cannot run on the grid of the scene's box (see the file comment).
  Eigen::VectorXd initial_guess(const StepView& view) override;

  /// The gather path alone: the values of `world`'s contacts read back from a raw label grid
  /// `labels` [1, 2, ny, nx] (NCHW, the data set's layout) with the Shepard read-back, in row
  /// order, projected into the bounds when `project`. initial_guess() is features → predict
  /// → this (+ λ_prev for a residual model, then projected).
  Eigen::VectorXd guess_from_labels(const World& world, const Tensor& labels, bool project = true);
  /// The same from the network's output `y` [1, 2, ny, nx] in standardised units
  /// (Model::network_output): only the stencil nodes of the contacts are converted to labels
  /// (Model::label_value), so the result equals guess_from_labels(world, predict(features))
  /// bit for bit at a fraction of the cost. initial_guess() uses this. `contact_weights`:
  /// the kernel-weight field S of world's contact points (FeatureImageBuilder::contact_weights()
  /// after features() of this step), which the Shepard read-back then reuses instead of
  /// splatting it again (the same bits); null = rebuild it.
  Eigen::VectorXd guess_from_output(const World& world, const Tensor& y, bool project = true,
                                    const SphGrid* contact_weights = nullptr);

  [[nodiscard]] const CnnTiming& last_timing() const { return last_; }
  [[nodiscard]] const CnnTiming& total_timing() const { return total_; }
  /// The model. A caller may change its weights or statistics through it: the compiled
  /// inference plan is dropped here and rebuilt from the model at the next use.
  [[nodiscard]] Model& model() {
    plan_.reset();
    return model_;
  }
  /// What initial_guess() runs the network with: the model compiled for `world`'s grid
  /// (prepared for its box, as initial_guess() does) into a fused, one-thread InferencePlan.
  /// Its run(features, stencil nodes) equals Model::network_output_at bit for bit.
  InferencePlan& inference_plan(const World& world);

 private:
  /// (Re)builds the feature builder and transfer for the scene's box, sizes the network
  /// for its grid (ConfigError when the network cannot run there) and compiles the
  /// inference plan when missing.
  void prepare(const World& world);
  /// The grid nodes (j·nx + i) of the bilinear stencils of world's contacts, each once; the
  /// stencils themselves (one per contact, in order) are left in stencils_.
  std::span<const int> stencil_nodes(const World& world);
  /// guess_from_output without the checks and the projection, for w's contacts (at least
  /// one) whose stencil_nodes() were just listed: `nodes` and stencils_ are that call's.
  Eigen::VectorXd read_back_output(const World& w, const Tensor& y, std::span<const int> nodes,
                                   const SphGrid* contact_weights);
  /// The read-back of grid_ at w's contacts, per row: Shepard, or the gain read-back (λp·ĝ).
  /// `weights`: S of w's contact points when already splatted (Shepard only), else null.
  /// `stencils`: the contacts' bilinear stencils when at hand (one per contact; otherwise
  /// computed from the points), used by the Shepard read-back with given weights.
  Eigen::VectorXd read_back_grid(const World& w, const SphGrid* weights = nullptr,
                                 std::span<const BilinearStencil> stencils = {});

  Model model_;
  std::string name_;
  bool hybrid_;
  int threads_;
  std::optional<FeatureImageBuilder> builder_;
  std::optional<SphTransfer> transfer_;
  std::optional<InferencePlan> plan_;  ///< the model compiled for inference (prepare())
  double box_w_ = -1, box_h_ = -1;
  Tensor features_;
  SphGrid grid_;
  std::vector<Vec2> points_;
  std::vector<int> nodes_;       ///< stencil_nodes()
  std::vector<BilinearStencil> stencils_;  ///< stencil_nodes(): one per contact
  std::vector<float> node_values_;      ///< guess_from_output: the stencil nodes' outputs → labels
  std::vector<double> readback_;        ///< read_back_grid with given weights: (λn, λt) per contact
  std::vector<std::uint8_t> unsupported_;  ///< its per-contact "no kernel support" flags
  std::vector<unsigned> stamp_;  ///< per grid node: the stencil_nodes() call that last listed it
  unsigned call_ = 0;
  CnnTiming last_, total_;
};

/// Registers "cnn" and "cnn-hybrid" (see the file comment) with `default_model` as the
/// model when neither the argument nor WarmStartEnv::model_path names one.
void add_cnn_warm_starters(WarmStarterRegistry& registry, std::filesystem::path default_model);

}  // namespace dc
