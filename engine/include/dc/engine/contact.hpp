#pragma once
// Contacts between circles and between a circle and a wall.
//
// A Contact is the persistent description of one touching (or nearly touching) pair in a
// step: its feature key, geometry, and the impulse-free force λ = [λ_n, λ_t] it carried
// when solved. The per-step solver rows are derived from it (see Assembly); the contact
// owns its solved forces so warm starters can match them by key in the next step.
#include <compare>
#include <cstdint>
#include <functional>
#include <span>
#include <string>
#include <vector>

#include "dc/core/vec2.hpp"

namespace dc {

/// Wall identifiers: walls appear as negative "body" indices in contacts and files.
enum class Wall : int { Left = -1, Right = -2, Bottom = -3, Top = -4 };

/// Name of a wall id ("left", ...), or "body" for non-negative ids.
const char* wall_name(int id);

/// Persistent feature key of a contact. For two circles: a < b are the body indices.
/// For a circle and a wall: a is the wall id (negative), b the body index. `feature` tells
/// several contact points of one pair apart (e.g. the two points of a polygon edge on a
/// face); circles have one point per pair, feature 0. Keys order contacts deterministically
/// (wall contacts first, then pairs in index order, then by feature).
struct ContactKey {
  int a = 0;
  int b = 0;
  int feature = 0;

  static ContactKey pair(int i, int j, int feature = 0) {
    return i < j ? ContactKey{i, j, feature} : ContactKey{j, i, feature};
  }
  static ContactKey wall(Wall w, int body, int feature = 0) { return ContactKey{static_cast<int>(w), body, feature}; }
  [[nodiscard]] bool is_wall() const { return a < 0; }
  [[nodiscard]] std::uint64_t packed() const {
    return (static_cast<std::uint64_t>(static_cast<std::uint32_t>(a)) << 32) |
           static_cast<std::uint32_t>(b);
  }
  friend auto operator<=>(const ContactKey&, const ContactKey&) = default;
  friend bool operator==(const ContactKey&, const ContactKey&) = default;
};

struct ContactKeyHash {
  std::size_t operator()(const ContactKey& k) const noexcept {
    // splitmix64 finaliser: cheap and well mixed for sequential indices.
    std::uint64_t z = k.packed() + 0x9e3779b97f4a7c15ULL +
                      static_cast<std::uint64_t>(static_cast<std::uint32_t>(k.feature)) * 0xd6e8feb86659fd93ULL;
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
    return static_cast<std::size_t>(z ^ (z >> 31));
  }
};

struct Contact {
  ContactKey key;
  int body_a = 0;       ///< first body, or wall id (< 0); the normal points from a to b
  int body_b = 0;       ///< second body (always a circle, ≥ 0)
  Vec2 point;           ///< contact point p [m]: midway between the two surfaces
  Vec2 normal;          ///< unit normal n from a to b (from the wall into the body)
  double gap = 0.0;     ///< signed distance between surfaces [m]; < 0 is penetration
  double lambda_n = 0;  ///< solved normal force [N] (after the step's solve)
  double lambda_t = 0;  ///< solved friction force along t = perp(n) [N]
  /// Restitution memory (restitution.hpp), kept by World::collide only when e > 0: the
  /// relative normal velocity J_n u [m/s] this contact approached with (< 0: closing) …
  double approach_velocity = 0;
  /// … and whether this step's normal row aims at the bounce −e·approach_velocity.
  bool restitution_due = false;
  /// Witness points on each surface in the body frames of a and b (a wall's: the world point
  /// on its plane); set by the shape narrow phase, where contact_gap() re-measures the gap of a
  /// pair with a non-circle as n·(p_b − p_a) from them. Unused for circle pairs.
  Vec2 anchor_a, anchor_b;
};

/// One contact's solved forces [N] packed apart from its Contact (World keeps a list's λ so
/// between integrate() and the list's next read): λ_n and λ_t (0 when it has no tangent row).
struct ContactLambda {
  double n = 0;
  double t = 0;
};

/// For each contact of `current`, the index of the contact with the same key in `previous`,
/// or −1 if it is new this step: the persistent-contact matching behind the `builtin` warm
/// start. Both lists must be sorted by key (World keeps them so); one merge pass, O(C).
/// Throws InvalidArgument naming the list if one is not sorted by key.
std::vector<int> match_contacts_by_key(std::span<const Contact> previous, std::span<const Contact> current);

}  // namespace dc
