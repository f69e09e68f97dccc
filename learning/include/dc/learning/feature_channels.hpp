#pragma once
// The feature channels a model reads and the definition of its feature image: what the grid
// values mean; dc/cnn/feature_image.hpp computes them. The formulas and units of every
// channel and of the labels are in docs/formats.md "Channels" (shape channels:
// docs/learning.md "Shape channels"). In short, on the nodes x of an SphTransferDef grid with
// the 2D-normalised kernel W [1/m²]: body channels are Σ_k W m_k [kg/m²] or Shepard averages
// Σ_k W v_k / Σ_k W (0 where Σ_k W = 0); per-contact channels (lambda_prev_*, vrel_*, gap,
// w_prev_*) are Shepard numerators Σ_c W q_c on the same kernel and points as the labels
// G = Σ_c W λ*_c [N/m²], so label − lambda_prev is the splat of λ* − λ_prev. A builder whose
// list names no shape channel computes no shape grid, so its images do not depend on them.
// Storage: NCHW float32 as SphGrid, value(c, j, i) at (c·ny + j)·nx + i, row j = y = j·d,
// j = 0 the bottom of the box (no flip); values computed in double and rounded to float.
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "dc/sph/sph_transfer.hpp"

namespace dc {

/// One feature channel (see the file comment for the formulas).
enum class FeatureChannel {
  Mass, Vx, Vy, Omega, ContactDensity, Nx, Ny, LambdaPrevN, LambdaPrevT, VrelN, VrelT, Gap,
  Coverage, OrientC, OrientS, WPrevN, WPrevT
};

/// "mass", "vx", "vy", "omega", "contact_density", "nx", "ny", "lambda_prev_n", "lambda_prev_t",
/// "vrel_n", "vrel_t", "gap", "coverage", "orient_c", "orient_s", "w_prev_n", "w_prev_t".
const char* to_string(FeatureChannel c);
/// Inverse of to_string; ConfigError listing the valid names otherwise.
FeatureChannel parse_feature_channel(std::string_view name);
/// A comma-separated list of channel names (no duplicates, at least one); ConfigError otherwise.
std::vector<FeatureChannel> parse_feature_channels(const std::string& list);
/// Names of a channel list, in order.
std::vector<std::string> feature_channel_names(std::span<const FeatureChannel> channels);
/// mass, vx, vy, omega, contact_density.
std::vector<FeatureChannel> default_feature_channels();
/// The channels of a residual model (the shipped one): mass, vx, vy, omega, contact_density,
/// lambda_prev_n, lambda_prev_t, vrel_n, vrel_t, gap.
std::vector<FeatureChannel> residual_feature_channels();
/// residual_feature_channels() plus w_prev_n, w_prev_t (the builtin guess's LCP velocity).
std::vector<FeatureChannel> residual_w_feature_channels();
/// True when the list needs the step's LcpProblem (w_prev_n, w_prev_t).
bool needs_lcp_problem(std::span<const FeatureChannel> channels);
/// Channels of a label image: λ_n, λ_t.
inline constexpr int kLabelChannelCount = 2;
/// "lambda_n", "lambda_t".
std::vector<std::string> label_channel_names();

/// What a FeatureImageBuilder computes. `sph.grid.channels` and `sph.normalisation` are
/// ignored (the builder sets them): feature fields are Shepard averages and labels are
/// Shepard numerators by definition.
struct FeatureImageDef {
  SphTransferDef sph;                                              ///< box, d, kernel, h
  std::vector<FeatureChannel> channels = default_feature_channels();
  /// The default setting (default_sph_setting) on a W × H box with the default channels.
  static FeatureImageDef for_box(double width, double height);
  /// Throws ConfigError naming the field (bad grid/kernel, empty or duplicate channels).
  void validate() const;
};

}  // namespace dc
