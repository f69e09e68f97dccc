#pragma once
// The engine-internal body order behind stable external indices (`[bodies] internal_order =
// "morton"`, docs/engine.md "Spatial body order"). World keeps its working copy of the bodies
// here, sorted by the Morton code of each body's current cell and re-sorted every K steps, so
// that the broad phase's pairs, the contacts, the LCP rows (contacts sorted by internal key)
// and J's columns follow space and every stage walks memory with locality. The public
// objects stay in external order: this class translates contacts (body ids, key, normal
// orientation) and per-row vectors between the two orders, and copies body state both ways.
//
// Orientation: a pair contact's normal points from the lower to the higher body index. When
// the internal order of a pair's bodies is the reverse of their external order, the external
// contact has its bodies swapped and n (so t = perp(n)) negated. Its rows of J are the same
// per body (−n on a, +n on b becomes +n on the old a, −n on the old b: the same entries), so
// b, λ_n and λ_t are the same numbers in both orders; only the columns move.
#include <Eigen/Core>
#include <vector>

#include "dc/engine/body_state.hpp"
#include "dc/engine/contact.hpp"
#include "dc/engine/contact_constraints.hpp"

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
  /// fewer bodies than before or a shape table (the internal order is for circle-only scenes).
  void update_from(const BodyState& external, bool copy_all);
  /// Re-sorts the internal order by the Morton code of each body's current cell (side `cell`
  /// [m]; morton_order, ties by current internal index): deterministic.
  void resort(double cell);
  /// Copies the kinematic state (x, θ, v, ω) of every body to its external index.
  void gather_kinematics(BodyState& external) const;

  /// `external` ← `internal` contacts with external body ids and keys, sorted by key (a
  /// counting sort by the key's first index, then by the rest within each bucket), and
  /// remembers for each external contact its internal contact and orientation.
  void contacts_to_external(const std::vector<Contact>& internal, int bodies, std::vector<Contact>& external);
  /// Internal contact of external contact c (of the last contacts_to_external).
  [[nodiscard]] int internal_contact(int c) const { return internal_of_contact_[static_cast<std::size_t>(c)]; }
  /// Row vector of the internal problem from one of the external problem (same contacts).
  void rows_to_internal(const ContactConstraints& external, const ContactConstraints& internal,
                        const Eigen::VectorXd& lambda_external, Eigen::VectorXd& lambda_internal) const;
  /// Row vector of the external problem from one of the internal problem.
  void rows_to_external(const ContactConstraints& external, const ContactConstraints& internal,
                        const Eigen::VectorXd& lambda_internal, Eigen::VectorXd& lambda_external) const;

 private:
  BodyState state_;
  std::vector<int> external_of_;
  std::vector<int> internal_of_contact_;
  std::vector<unsigned char> flipped_;  ///< per internal contact: bodies in reverse external order
  std::vector<int> bucket_start_;      ///< contacts_to_external's counting sort (reused)
  std::vector<ContactKey> keys_;       ///< external key of each internal contact (reused)
  std::vector<int> sorted_;            ///< internal contacts in external key order (reused)
};

}  // namespace dc
