#pragma once
// Feature and label images of one simulation step: the channels defined in
// dc/learning/feature_channels.hpp (formulas, units, storage order there), computed from the
// bodies, this step's contacts, the previous step's solved contacts and the step's LCP.
#include <cstddef>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include "dc/cnn/shape_samples.hpp"
#include "dc/engine/body_state.hpp"
#include "dc/engine/contact.hpp"
#include "dc/lcp/lcp_problem.hpp"
#include "dc/learning/feature_channels.hpp"
#include "dc/sph/sph_grid.hpp"
#include "dc/sph/sph_kernel.hpp"
#include "dc/sph/sph_transfer.hpp"

namespace dc {

/// Builds feature and label images; owns its scratch grids (no allocation after the first
/// step of a given size). Not thread-safe: use one per thread.
class FeatureImageBuilder {
 public:
  /// Validates `def` and allocates the grids.
  explicit FeatureImageBuilder(FeatureImageDef def);

  [[nodiscard]] const FeatureImageDef& def() const { return def_; }
  [[nodiscard]] int nx() const { return nx_; }  ///< columns (x)
  [[nodiscard]] int ny() const { return ny_; }  ///< rows (y)
  [[nodiscard]] int feature_channels() const { return static_cast<int>(def_.channels.size()); }
  static constexpr int kLabelChannels = kLabelChannelCount;
  [[nodiscard]] std::size_t feature_size() const { return feature_channels() * plane(); }  ///< Cf·ny·nx
  [[nodiscard]] std::size_t label_size() const { return kLabelChannels * plane(); }       ///< 2·ny·nx
  [[nodiscard]] std::size_t plane() const { return static_cast<std::size_t>(nx_) * ny_; }

  /// The feature image of a step: bodies as they are before the solve, this step's contacts
  /// (key, point, normal, gap; not their λ) and the previous step's solved contacts
  /// (`previous`: key-sorted, with λ; only read by the lambda_prev channels, empty = every
  /// contact is new). `out` must hold feature_size() floats. Throws InvalidArgument on a size
  /// mismatch, unsorted contact lists or non-finite input.
  /// `problem` is the step's assembled LCP (rows ordered by `contacts`, as World::problem()):
  /// only read by the w_prev channels, which throw InvalidArgument when it is null.
  /// `match`: match_contacts_by_key(previous, contacts) when the caller has it already (one
  /// entry per contact, read by the lambda_prev and w_prev channels instead of matching the
  /// keys again); empty = matched here.
  void features(const BodyState& bodies, std::span<const Contact> contacts, std::span<const Contact> previous,
                const LcpProblem* problem, std::span<float> out, std::span<const int> match = {});
  /// The same without a problem (no w_prev channel may be listed).
  void features(const BodyState& bodies, std::span<const Contact> contacts, std::span<const Contact> previous,
                std::span<float> out) {
    features(bodies, contacts, previous, nullptr, out);
  }
  /// The same with no previous contacts.
  void features(const BodyState& bodies, std::span<const Contact> contacts, std::span<float> out) {
    features(bodies, contacts, {}, nullptr, out);
  }

  /// The label image: Shepard numerators of (λ_n, λ_t) at the contact points. `lambda` is
  /// contact-major (λ_n,c, λ_t,c) pairs, 2·contacts.size() values. `out` must hold
  /// label_size() floats.
  void labels(std::span<const Contact> contacts, std::span<const double> lambda, std::span<float> out);

  /// The kernel-weight field S(node) = Σ_contacts W(|x_node − q_c|) of the contact points of
  /// the last features() call — the Shepard denominator of a read-back at those contacts —
  /// when one of the channels needed it (contact_density, nx, ny); null otherwise.
  [[nodiscard]] const SphGrid* contact_weights() const {
    return has_contact_weights_ ? &contact_weight_ : nullptr;
  }
  /// The node rows [lo, hi] (inclusive; lo > hi: none) outside which the last features()
  /// call wrote +0 into every channel: the rows its splats reach (InferencePlan::InputRows).
  [[nodiscard]] std::pair<int, int> nonzero_rows() const { return {rows_lo_, rows_hi_}; }

 private:
  /// The node rows of one features() call: [clear_lo, clear_hi] the rows its splats clear (the
  /// grids are zero elsewhere), [lo, hi] the union of the rows they wrote.
  struct SplatRows {
    int clear_lo, clear_hi;
    int lo, hi;
  };
  // The steps of features(), in call order; each fills points_/values_ and splats them.
  void mark_written(int row_lo, int row_hi, SplatRows& rows);
  void splat_points(SphGrid& grid, SphGrid* weights, SplatRows& rows);
  void splat_bodies(const BodyState& bodies, SplatRows& rows);
  /// Returns whether the contact density is left to the per-contact values' splat.
  bool splat_contact_fields(const BodyState& bodies, std::span<const Contact> contacts, SplatRows& rows);
  void splat_contact_values(const BodyState& bodies, std::span<const Contact> contacts,
                            std::span<const Contact> previous, std::span<const int> match, bool density_with_values,
                            SplatRows& rows);
  void splat_w_prev(const BodyState& bodies, std::span<const Contact> contacts, std::span<const Contact> previous,
                    const LcpProblem& problem, std::span<const int> match, SplatRows& rows);
  void splat_shapes(const BodyState& bodies, SplatRows& rows);
  /// The grids' rows [lo, hi] as the float channels of `out` (+0 elsewhere).
  void write_channels(std::span<float> out, int lo, int hi);

  FeatureImageDef def_;
  SphKernel kernel_;
  int nx_ = 0, ny_ = 0;
  SphGrid body_grid_;     // 4 channels: Σ W m, Σ W vx, Σ W vy, Σ W ω
  SphGrid body_weight_;   // Σ W over body centres
  SphGrid contact_grid_;  // 2 channels: Σ W nx, Σ W ny
  SphGrid contact_weight_;
  bool has_contact_weights_ = false;  // contact_weight_ holds the last features() call's S
  SphGrid contact_values_;  // 5 channels: Σ W λ_prev,n, Σ W λ_prev,t, Σ W vrel_n, Σ W vrel_t, Σ W gap
  SphGrid w_prev_grid_;     // 2 channels: Σ W w_n, Σ W w_t at λ_prev
  SphGrid shape_grid_;      // 3 channels: Σ W a, Σ W a Q_x, Σ W a Q_y over the area samples
  SphTransfer label_transfer_;  // Shepard, 2 channels: the labels are its splat()
  std::vector<Vec2> points_;
  std::vector<double> values_;
  std::vector<AreaSample> samples_;
  std::vector<double> ratio_;  // one plane: the Shepard quotients before their float conversion
  int dirty_lo_ = 0, dirty_hi_ = -1;  // every grid above is zero outside these node rows (empty: all zero)
  int rows_lo_ = 0, rows_hi_ = -1;    // nonzero_rows() of the last features() call
};

}  // namespace dc
