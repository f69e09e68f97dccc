#pragma once
// The feature channels a model reads and the definition of its feature image — what the grid
// values MEAN; dc/cnn/feature_image.hpp computes them from a simulation step.
//
// Feature and label images of one simulation step on the SPH grid of the box (docs/design.md §4, §5;
// docs/formats.md "Data set"). The CNN maps the feature image to the label image; the label
// image read back at the contact points (SphTransfer::gather, Shepard) is the warm start.
//
// Grid and kernel: those of an SphTransferDef (default: default_sph_setting(W, H), i.e. the
// setting the bench's `sph` starter uses — poly6, d = h = 0.5 ⇒ 61 × 61 on 30 × 30). With
// W(r) = W(|x_node − q|, h) [1/m²] the channels are, at every node x:
//
//   mass             Σ_k W(|x − x_k|) m_k                       [kg/m²]  (a mass density)
//   vx, vy           Σ_k W v_k / Σ_k W   (0 where Σ_k W = 0)    [m/s]    (Shepard average)
//   omega            Σ_k W ω_k / Σ_k W   (0 where Σ_k W = 0)    [rad/s]
//   contact_density  Σ_c W(|x − p_c|)                           [1/m²]   (this step's contact
//                                                                         points, known before the solve)
//   nx, ny           Σ_c W n_c / Σ_c W   (0 where Σ_c W = 0)    [1]      (contact normals)
//   lambda_prev_n,   Σ_c W λ_prev,c                              [N/m²]   (the builtin warm start on
//   lambda_prev_t                                                          the grid: the previous step's
//                                                                          solved λ of the contact with the
//                                                                          same key, 0 for a new contact)
//   vrel_n, vrel_t   Σ_c W (u_b − u_a)·n_c, ·t_c                 [m/s/m²] (relative velocity of the two
//                                                                          contact points before the solve,
//                                                                          u = v + ω × (p_c − x); a wall's
//                                                                          u is 0; t = perp(n))
//   gap              Σ_c W g_c                                   [m/m²]   (signed gap, < 0 penetration)
//   w_prev_n,        Σ_c W w_c,n, Σ_c W w_c,t with w = A λ_prev + b [m/s/m²] (the LCP's contact velocity
//   w_prev_t                                                               AFTER builtin's impulses: where
//                                                                          and how much builtin's guess
//                                                                          violates the LCP; needs the step's
//                                                                          LcpProblem)
//   coverage         C(x) = Σ_k Σ_s W(|x − y_ks|) a_ks            [1]      (area fraction: bodies' real extent)
//   orient_c,        Σ_k Σ_s W a_ks Q_k / C   (0 where C = 0)     [1]      (nematic orientation of the shape,
//   orient_s                                                               Shepard average over the area samples)
//
// over bodies k (centres x_k) and this step's contacts c (points p_c, normals n_c). The
// per-contact channels lambda_prev_*, vrel_*, gap are Shepard NUMERATORS like the labels
// (same kernel, same points): a label minus lambda_prev is the splat of λ* − λ_prev, the
// target of a residual model (labels.hpp, LabelKind::Residual). vrel and gap are what the
// LCP's b is made of (b_n = vrel_n + Δt g·n + gap terms, engine/src/assembly/assembly.cpp).
// w_prev is the right-hand side of the correction: for the rows that stay active the exact
// correction δ = λ* − λ_prev solves A δ = −w_prev, so a predictor of δ is a learned
// (non-local) inverse of A applied to it — where builtin is right, w_prev is ≈ 0.
// The default feature set is mass, vx, vy, omega, contact_density.
//
// Shape channels (docs/learning.md "Shape channels"). mass/vx/vy/omega splat each body at
// its centre of mass only, so
// a box, a thin ellipse and a circle of equal mass look the same and a box's orientation is
// lost. coverage splats area samples y_ks = x_k + R(θ_k) p_s of the body's real extent
// (shape_samples.hpp: sub-triangle centroids of the polygon's fan, the inscribed 16-gon for
// circles and ellipses, spacing ≤ h/2, weights a_ks summing to the body's area A_k). With the
// 2D-normalised kernel (∫ W dA = 1) it integrates to the covered area, ∫ C dA = Σ_k A_k, and
// is ≈ 1 inside a body, 0 far outside (the area fraction smoothed over h). Q_k = R(2θ_k) q_k
// is the body's nematic vector α (cos 2φ, sin 2φ) from its second area moment (anisotropy α
// ∈ [0, 1], principal-axis angle φ; shape_samples.hpp): unchanged by θ → θ + π and by the
// symmetries of a box, and 0 for circles and regular polygons, whose moment is isotropic — so
// on a circle-only scene orient_c = orient_s = 0 and coverage is that of the discs. Static
// and kinematic bodies are splatted like dynamic ones (they are where contacts happen).
// Only a builder whose channel list names one of the three computes them, so images with the
// older channel lists are bit-identical to those of the builder before the shape channels existed.
//
// Labels (2 channels, λ_n then λ_t): the Shepard NUMERATOR grids
//
//   G_n(x) = Σ_c W(|x − p_c|) λ_n,c,   G_t(x) = Σ_c W(|x − p_c|) λ_t,c        [N/m²]
//
// exactly what SphTransfer::splat produces in Shepard mode, so SphTransfer::gather(G, p)
// (which divides by the interpolated weight field of the query points p, rebuilt from the
// points alone) reads λ back at the contacts — the `sph` warm starter's numbers.
//
// Storage: NCHW float32 exactly as SphGrid, channel-major, row j = y = j·d, column i = x = i·d,
// j = 0 is y = 0 (the bottom of the box; no flip, no transpose): value(c, j, i) at
// (c·ny + j)·nx + i. The values are computed in double and rounded once to float.
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
