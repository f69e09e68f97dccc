#pragma once
// Private to "pgs-colored" (pgs_colored_layout.hpp): where each body's Δu lives during the sweeps
// and in which order a colour's contacts fill its batches, chosen for locality between the
// threads. The sweeps' threads each take one region of the bodies in every colour (region_cuts,
// sweep_team.hpp: a cut in the batches' keys, the Δu slot of a batch's first lower body). In the
// engine's creation order body indices are spread at random over the pile, so a cut in body
// index gives each thread bodies all over it: most contacts join the two regions and the Δu
// lines travel between the cores at every colour. Here the dynamic bodies are numbered
// breadth-first on the contact graph (from a far end of each connected piece, so the numbers
// run across the piece in bands) and Δu slot k holds body numbered k; each colour's contacts
// are ordered by their lower slot, so a batch's lanes and each thread's batches hold
// neighbouring bodies and a cut in slot order is one short boundary through the pile.
//
// Neither changes a result bit: a body's Δu is the same sums wherever it is stored, and a
// colour's contacts touch disjoint bodies, so which lane or batch of the colour holds a contact
// changes none of its operations (θ is a max, the flag an or). The overflow set, swept in
// order, keeps contact order.
#include <cstdint>
#include <vector>

#include "dc/lcp/contact_constraints.hpp"

namespace dc::colored {

/// The storage of the numbering (kept by the solver between solves; no allocation in steady state).
struct BodyNumbering {
  std::vector<int> slot;   ///< body → Δu slot (a permutation of 0 … bodies − 1)
  std::vector<int> key;    ///< per contact: the lower Δu slot of its dynamic bodies (bodies: none)
  std::vector<int> order;  ///< every contact, stably sorted by key (order_by_key)
  std::vector<int> head, next, queue, mark;  // scratch: adjacency lists, the breadth-first queue
  int bodies = -1;  ///< the body count `slot` was numbered for (−1: none)
  int age = 0;      ///< fresh layouts since `slot` was numbered (−1: the identity, not chosen)
  /// The body order was local already when last numbered (cut_share): slot = body, contacts in
  /// contact order (which then follows the bodies) until the next numbering.
  bool local_already = false;
  /// A serial layout (no locality) numbers slot = body and sets the locality numbering aside
  /// here, for the next locality layout to take back: in contact order a permuted numbering
  /// scatters the Δu reads that slot = body keeps in body order (a serial solve after a
  /// threaded one swept up to 7 % slower, step_threads --at-rest --profile).
  std::vector<int> kept;
  bool set_aside = false;  ///< `kept` holds the locality numbering (slot is the identity)
  /// Fresh layouts after which the bodies are numbered again (the pile moves slowly; the
  /// numbering only decides locality, never a result).
  static constexpr int kRenumberEvery = 32;
};

/// Numbers the bodies breadth-first on the contacts between dynamic bodies (each connected piece
/// from the body last reached by a breadth-first pass from its lowest body: a far end), pieces
/// in order of their lowest body, then the bodies in no contact in index order: n.slot. Serial,
/// O(bodies + contacts).
void number_bodies(const ContactConstraints& cons, const std::vector<std::uint8_t>& dynamic, int bodies,
                   BodyNumbering& n);

/// The share of the contacts between two dynamic bodies that a cut at the middle of the numbers
/// of the bodies in such contacts separates, with the numbering `slot` (nullptr: slot = body):
/// how many Δu lines two threads' regions would share. Serial, O(bodies + contacts).
double cut_share(const ContactConstraints& cons, const std::vector<std::uint8_t>& dynamic, int bodies,
                 const int* slot, BodyNumbering& n);

/// n.key per contact (from n.slot) and n.order: every contact, stably sorted by key (a counting
/// sort over the slots), O(bodies + contacts); on up to `threads` members of the calling thread's
/// team (each a block of the contacts; serial below a few thousand contacts), the same order.
void order_by_key(const ContactConstraints& cons, const std::vector<std::uint8_t>& dynamic, int bodies,
                  BodyNumbering& n, int threads = 1);

}  // namespace dc::colored
