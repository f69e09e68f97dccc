#pragma once
// The engine-internal body order behind stable external indices (`[bodies] internal_order =
// "morton"`, docs/engine.md "Engine-internal order"). World's working copy of the bodies is
// sorted by the Morton code of each body's current cell, re-sorted when the order has decayed
// (or every `resort_every` steps), so the pairs, contacts, LCP rows and J's columns follow space.
// The public objects stay in external order: this class translates contacts and per-row vectors
// and copies body state both ways; World translates lazily, only the views a caller reads.
// Orientation: a pair contact's normal points from the lower to the higher body index; when the
// internal order of a pair is the reverse of the external one, the external contact has its
// bodies swapped and n (so t = perp(n)) negated — the same J entries per body up to the sign of a
// zero r × n, so b, λ_n, λ_t are the same numbers. The public problem is therefore assembled from
// the public contacts, not permuted from the internal one (−0 and +0 entries of J would differ).
#include <Eigen/Core>
#include <cstdint>
#include <vector>

#include "dc/engine/body_state.hpp"
#include "dc/engine/contact.hpp"
#include "dc/lcp/contact_constraints.hpp"

namespace dc {

class InternalBodyOrder {
 public:
  /// The bodies in internal order (World's working state).
  [[nodiscard]] BodyState& state() { return state_; }
  [[nodiscard]] const BodyState& state() const { return state_; }
  /// External index of internal body i.
  [[nodiscard]] const std::vector<int>& external_of() const { return external_of_; }

  /// Brings the internal state up to date with `external`: bodies appended to it since the
  /// last call join at the end of the internal order; with `copy_all` every body's fields are
  /// copied (edits made through World::bodies()). Throws InvalidArgument when `external` has
  /// fewer bodies than the last call or a shape table (the internal order is for circle-only scenes).
  void update_from(const BodyState& external, bool copy_all);
  /// Re-sorts the internal order by the Morton code of each body's current cell (side `cell`
  /// [m]; morton_order, ties by current internal index): deterministic.
  void resort(double cell);
  /// Moves contacts keyed in the internal order before the last resort() to the current one:
  /// new body ids and keys, the normal and anchors turned where a pair's bodies changed order
  /// (as contacts_to_external does), sorted by key again. Their external view is unchanged.
  void rekey(std::vector<Contact>& contacts) const;
  /// Copies the kinematic state (x, θ, v, ω) of every body to its external index.
  void gather_kinematics(BodyState& external) const;

  /// For each external contact c (the contacts `internal` translated and sorted by external
  /// key: a counting sort by the key's first index, then by the rest within each bucket) the
  /// internal contact it comes from: internal_of[c].
  void external_order(const std::vector<Contact>& internal, int bodies, std::vector<int>& internal_of) const;
  /// external_order() reading the keys from `assembled`, the constraints assembled from
  /// `internal` (same count, contact by contact; a circle-only state, whose constraints name
  /// each contact's bodies and feature): the same internal_of from a smaller stream. Throws
  /// InvalidArgument when the counts differ.
  void external_order(const std::vector<Contact>& internal, const ContactConstraints& assembled, int bodies,
                      std::vector<int>& internal_of) const;
  /// `external` ← the contacts `internal` with external body ids and keys, in the order
  /// `internal_of` of external_order().
  void contacts_to_external(const std::vector<Contact>& internal, const std::vector<int>& internal_of,
                            std::vector<Contact>& external) const;
  /// `external` ← what assembly reads of the bodies (x, v, ω, 1/m, 1/I; no shapes), by external
  /// index, from internal kinematic arrays (the current state's or a copy taken before an
  /// integrate) and the internal constants: assembling the external contacts on it gives the
  /// public problem bit for bit as assembling them on the public bodies did at that time.
  void bodies_for_assembly(const std::vector<Vec2>& position, const std::vector<Vec2>& velocity,
                           const std::vector<double>& omega, BodyState& external) const;
  /// Row vector of the internal problem from one of the external problem (same contacts).
  static void rows_to_internal(const ContactConstraints& external, const ContactConstraints& internal,
                               const std::vector<int>& internal_of, const Eigen::Ref<const Eigen::VectorXd>& lambda_external,
                               Eigen::VectorXd& lambda_internal);
  /// Row vector of the external problem from one of the internal problem. The external rows
  /// are numbered as assembly numbers them (contact by contact: normal row, then the tangent
  /// row when μ > 0), so the external constraints need not exist.
  static void rows_to_external(const ContactConstraints& internal, const std::vector<int>& internal_of,
                               const Eigen::Ref<const Eigen::VectorXd>& lambda_internal, Eigen::VectorXd& lambda_external);

  /// Decay measure of the order: Σ |i − j| over the pair contacts (i, j internal body indices)
  /// and their number. Right after a re-sort the pairs in contact are mostly neighbours in
  /// memory; as bodies move, their partners drift away in the order and the sum grows.
  struct Spread {
    std::int64_t sum = 0;
    std::int64_t pairs = 0;
  };
  [[nodiscard]] static Spread pair_spread(const std::vector<Contact>& internal);

 private:
  /// External view of one internal contact (id, key, orientation).
  [[nodiscard]] Contact external_contact(const Contact& internal) const;
  /// internal_of ← the contacts sorted by their external keys keys_ (a counting sort by the
  /// key's first index, then by the rest within each bucket).
  void sort_by_keys(int bodies, std::vector<int>& internal_of) const;

  BodyState state_;
  std::vector<int> external_of_;
  std::vector<int> new_of_old_;  ///< internal index after the last resort() of each index before it
  // external_order()'s scratch (reused; mutable: the translation is a const view of the order).
  mutable std::vector<int> bucket_start_;
  mutable std::vector<ContactKey> keys_;
  mutable std::vector<int> sorted_;
};

}  // namespace dc
