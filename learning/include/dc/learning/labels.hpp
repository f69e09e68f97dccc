#pragma once
// What a model's label grid is (docs/learning.md "Residual models", "Label scale"): one
// definition used in both directions.
//   training:  label L (Shepard numerators of λ*) ── residual: L − lambda_prev channels
//              ── asinh(L / s) (s = LabelDef::scale > 0) ──▶ the network's target
//   read-back: output ── s·sinh(y) (expand_labels) ──▶ label grid ── SPH gather ──▶ δ
//              ── residual: δ ← sign(δ)·max(|δ| − τ, 0) (τ = LabelDef::deadzone),
//                 λ⁰ = λ_prev (by key) + δ;  absolute: λ⁰ = δ  ──▶ projected into the bounds.
#include <span>
#include <string_view>
#include <utility>
#include <vector>

#include "dc/learning/feature_channels.hpp"
#include "dc/learning/tensor.hpp"

namespace dc {

/// What the label grid of a model means.
enum class LabelKind {
  Absolute,  ///< the Shepard numerators of λ* (the data set's labels)
  Residual,  ///< the numerators of λ* − λ_prev: the data set's labels minus lambda_prev_n/t
  /// A gain field g (values, not numerators): λ⁰ = λ_prev (1 + ĝ) with ĝ the load-weighted
  /// read-back of g (contact_readback.hpp). Trained through PGS only (no label grid: the target
  /// needs per-contact λ_prev·λ*); `train --loss pgs-* --gain` starts one from a residual model.
  Gain,
};
/// True for the kinds whose guess is λ_prev + a correction (residual, gain).
inline bool is_corrective(LabelKind k) { return k != LabelKind::Absolute; }
/// "absolute" / "residual" / "gain" (the text stored in model files, /grid label_kind).
const char* to_string(LabelKind kind);
/// Inverse of to_string; ConfigError "label kind 'x': expected absolute, residual or gain" otherwise.
LabelKind parse_label_kind(std::string_view text);

/// A model's label definition (ModelGrid::labels; persisted in the model file's /grid).
struct LabelDef {
  LabelKind kind = LabelKind::Absolute;
  /// Output compression s ≥ 0 [label units]. s > 0: the network learns y = asinh(label / s)
  /// (standardised), so that small labels keep their precision next to heavy-tailed large
  /// ones (impacts carry 10³ N against a 50 N resting load); Model::predict returns
  /// s·sinh(y). 0 = labels as they are. (File attribute label_scale.)
  double scale = 0.0;
  /// Residual models: soft threshold τ ≥ 0 [N] on the read-back correction of every row,
  /// δ ← sign(δ)·max(|δ| − τ, 0), before it is added to λ_prev. A correction within the
  /// network's noise level leaves builtin's value alone: where builtin is already exact a small
  /// noisy correction costs PGS sweeps (docs/learning.md "Residual models"). 0 = off.
  /// (File attribute correction_deadzone.)
  double deadzone = 0.0;
  /// ConfigError naming the field: scale or deadzone negative or not finite.
  void validate() const;
  friend bool operator==(const LabelDef&, const LabelDef&) = default;
};

/// The label compression of a model (LabelDef::scale): asinh(v / s) and its inverse,
/// elementwise; the identity for s = 0. The inverse s·sinh(v) is evaluated in float as
/// float(s) · sinh(v) with a deterministic, vectorised sinh (learning/src/det_sinh.hpp: the
/// same bits in every build; within the last bit of glibc's sinhf).
void compress_labels(Tensor& labels, double scale);
void expand_labels(Tensor& labels, double scale);
/// expand_labels on a span of values (the cnn starter expands only the nodes it reads back).
void expand_label_values(std::span<float> values, double scale);

/// The indices of the lambda_prev_n and lambda_prev_t channels in `channels`, which a
/// residual model needs; ConfigError naming the missing channel (prefixed by `what`).
std::pair<int, int> lambda_prev_channels(std::span<const FeatureChannel> channels, std::string_view what);

/// The network's target for one sample, in place: `labels` [1, 2, ny, nx] (the data set's
/// Shepard numerators of λ*) becomes label − lambda_prev (residual) and then asinh(· / s).
/// `features` [1, C, ny, nx] is the sample's feature image with channels `channels`.
/// InvalidArgument on shape mismatch; ConfigError when a residual definition lacks the
/// lambda_prev channels.
void training_labels(Tensor& labels, const Tensor& features, std::span<const FeatureChannel> channels,
                     const LabelDef& def);

/// The soft threshold of residual read-backs: v ← sign(v)·max(|v| − τ, 0) for every value
/// (no-op for τ ≤ 0).
void apply_deadzone(std::span<double> values, double tau);

}  // namespace dc
