#pragma once
// Greedy graph colouring of a step's contacts for the colour-ordered PGS ("pgs-colored",
// docs/design.md §8.4 "Faster PGS"): no two contacts of one colour share a dynamic body, so the
// contacts of a colour can be solved at the same time (SIMD lanes, threads). Walls (body −1)
// and bodies with M⁻¹ = 0 (static, kinematic) do not conflict: the solver never writes them.
//
// Incremental: a ContactColorer remembers the colour of every contact of its last call,
// keyed by (lower body, other body, feature) — the contact's identity, as in ContactKey —
// and a contact that persists keeps its colour when that colour is still free on its
// bodies; the others (new contacts, lost colours) take the lowest free colour. Cost per call
// O(contacts + bodies): a per-body bit mask of used colours (find-first-zero of the OR of two
// masks) and a counting sort by body for next call's look-up; no hashing, no sort.
//
// Repeats. When the contacts' bodies and features (in the same order) and the dynamic flags equal the
// last call's, the last call had no overflow and each contact has a dynamic body, the rule
// above gives every contact its last colour (by induction over the contacts: the colours of the
// earlier contacts with its key are taken on the dynamic body they share, its own is free as
// last call's colouring is valid), so the call returns last call's result after one comparison
// pass (`repeated` set). A settled pile repeats its contact set for most steps.
//
// At most kMaxColors colours; a contact none of whose colours is free goes to the overflow
// set (colour kOverflow), which the solver runs serially after the colours (Box2D v3 does the
// same). With equal circles a body has ≤ 6 neighbours + 2 walls, so overflow does not occur.
#include <cstdint>
#include <span>
#include <vector>

#include "dc/engine/contact_constraints.hpp"

namespace dc {

struct ContactColoring {
  static constexpr int kMaxColors = 64;
  static constexpr int kOverflow = -1;
  std::vector<int> color;  ///< per contact: 0..colors−1, or kOverflow
  int colors = 0;          ///< number of colours used (max colour + 1)
  int reused = 0;          ///< contacts that kept last call's colour
  int overflow = 0;        ///< contacts in the overflow set
  bool repeated = false;   ///< the contacts' bodies equal the last call's: colours unchanged (see above)
  /// Counts the calls whose colours were computed (not repeated): equal generations, same colours.
  std::uint64_t generation = 0;
};

class ContactColorer {
 public:
  /// `reuse` = false colours every call from scratch (greedy in contact order).
  explicit ContactColorer(bool reuse = true) : reuse_(reuse) {}

  /// Colours `contacts`; `dynamic[k]` says whether body k conflicts (size ≥ 1 + max body).
  /// Throws InvalidArgument when a contact names a body outside `dynamic`.
  const ContactColoring& color(const ContactConstraints& contacts, std::span<const std::uint8_t> dynamic);

  /// The last call's result.
  [[nodiscard]] const ContactColoring& last() const { return out_; }
  /// Forgets the previous step's colours (the next call colours from scratch).
  void reset();

 private:
  struct Entry {
    int other;    // the second body (−1 for a wall)
    int feature;  // ContactConstraint::feature
    int color;
  };
  /// The contacts' (body_a, body_b, feature) and the flags equal the last call's.
  [[nodiscard]] bool same_as_last(const ContactConstraints& contacts, std::span<const std::uint8_t> dynamic) const;

  bool reuse_;
  ContactColoring out_;
  // Last call's input and whether a repeat of it keeps every colour (no overflow, every
  // contact on a dynamic body).
  struct Key {
    int body_a, body_b, feature;
  };
  std::vector<Key> last_keys_;
  std::vector<std::uint8_t> last_dynamic_;
  bool repeatable_ = false;
  // Last call's colours in CSR form by first body: entries_[start_[k] .. start_[k+1]).
  std::vector<int> start_;
  std::vector<Entry> entries_;
  std::vector<std::uint64_t> used_;  // per body: bit c set when colour c holds one of its contacts
  std::vector<int> scratch_;         // fill cursors of the counting sort
};

/// True when no two contacts of one colour (overflow excluded) share a body with dynamic[k] ≠ 0.
bool is_valid_coloring(const ContactConstraints& contacts, std::span<const std::uint8_t> dynamic,
                       const ContactColoring& coloring);

}  // namespace dc
