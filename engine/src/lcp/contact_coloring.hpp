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
//
// Threads. The result does not depend on the thread count: the contacts are split into
// max(1, contacts / chunk) chunks of equal size (a function of the contact count only), and
// chunk q owns the body range [L_q, L_{q+1}): L_0 = 0, L_q = the first body (lower body, or
// the body of a wall contact) of chunk q's first contact, kept ascending, L_last = bodies. A
// dynamic body is private to chunk q when it lies in q's range and no contact of another chunk
// touches it (every contact marks its dynamic bodies outside its chunk's range as shared: one
// value stored by any number of writers, so the marks do not depend on the threads either). A
// contact all of whose dynamic bodies are private to its chunk is interior, the others are
// boundary contacts. The rule above then runs in four phases:
//   1. the interior contacts keep their last colour where free (chunks in parallel),
//   2. the boundary contacts keep theirs (serial, in contact order),
//   3. the other interior contacts take the lowest free colour (chunks in parallel),
//   4. the other boundary contacts take theirs (serial, in contact order).
// A parallel phase reads and writes only the masks of its chunk's private bodies, so a chunk's
// result does not depend on which thread colours it or when, and every phase sees the same
// masks for any thread count. With one chunk (fewer than 2·chunk contacts) phases 1 and 3 are
// the serial greedy rule above, contact by contact. With several chunks the colours differ
// from the one-chunk rule only in the visiting order (interior contacts before boundary ones
// in each pass); the repeat shortcut stays exact, since its proof holds for any visiting order
// that keeps the contacts with one key in contact order (they share their bodies, so with a
// dynamic body they are all interior to one chunk or all boundary; contacts without one take
// the first entry of their key whatever the order, as no colour is ever taken on their bodies). Chunks of contacts in body order (as the
// benchmarks and a Morton-ordered engine give them) share the bodies of about one pile row:
// ≈ 300 boundary contacts per chunk edge on the 100-body-wide benchmark pile (900 of 19,900
// with 4 chunks). Contacts without spatial locality in their order (the benchmarks'
// interleaved order) are mostly boundary contacts: correct, but serial.
//
// The boundary contacts are coloured after the interior ones, on top: where all colours of
// the interior pattern are taken around them they need one more (hex pile: 5 colours instead
// of 4). Colouring them first was tried and gave 6.
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
  int chunks = 1;          ///< chunks coloured in parallel (see "Threads" above)
  int boundary = 0;        ///< contacts coloured serially after the chunks (phases 2 and 4)
  bool repeated = false;   ///< the contacts' bodies equal the last call's: colours unchanged (see above)
  /// Counts the calls whose colours were computed (not repeated): equal generations, same colours.
  std::uint64_t generation = 0;
};

class ContactColorer {
 public:
  /// Contacts per chunk of the parallel colouring ("Threads" above): ≈ 300 boundary
  /// contacts per chunk edge on the 10,000-body benchmark pile, so a chunk of 4,096 leaves
  /// ≈ 5 % of the contacts to the serial phases (2,048: 12 %; 1,024: 27 %).
  static constexpr int kChunk = 4096;

  /// `reuse` = false colours every call from scratch (greedy in contact order); `chunk` = the
  /// contacts per chunk of the parallel colouring (≥ 1; small values are for tests; kChunk is
  /// the measured choice), or 0 (the default) = always one chunk: the serial greedy rule, which
  /// on 2 threads still gives the faster sweeps (one colour fewer, results.md "Threads: the
  /// colouring in parallel"). Throws InvalidArgument for chunk < 0.
  explicit ContactColorer(bool reuse = true, int chunk = 0);

  /// Colours `contacts`; `dynamic[k]` says whether body k conflicts (size ≥ 1 + max body).
  /// `threads` (≥ 1) colour the chunks; the result is the same for every thread count.
  /// Throws InvalidArgument when a contact names a body outside `dynamic`.
  const ContactColoring& color(const ContactConstraints& contacts, std::span<const std::uint8_t> dynamic,
                               int threads = 1);

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
  /// Counts of one chunk's (or the serial phases') contacts, summed / maxed in chunk order.
  struct Tally {
    int reused = 0, overflow = 0, colors = 0;
  };
  /// Raw views of the per-call state for the colouring loops (contact_coloring.cpp): keeps the
  /// hot loops free of reloads through `this`.
  struct Canvas;
  /// First contact of chunk q of `chunks` over nc contacts (equal split; q = chunks gives nc).
  static int chunk_begin(int q, int chunks, int nc) {
    return static_cast<int>(static_cast<long long>(q) * nc / chunks);
  }
  // The steps of color(), in call order (contact_coloring.cpp).
  /// Sizes the per-call buffers for nc contacts on nb bodies and, with several chunks, the
  /// chunks' body ranges and a new stamp; returns the number of chunks.
  int prepare(const ContactConstraints& contacts, int nb);
  /// Pass 0 over chunk q: no colour yet, the pairs, the range check, the shared marks.
  void pair_chunk(int q, int chunks, const ContactConstraints& contacts, const std::uint8_t* dynamic, int nb,
                  const Canvas& canvas);
  /// Phase 1 over chunk q: interior contacts keep last call's colour (or, colouring from
  /// scratch with several chunks, take the lowest free one); boundary contacts are listed.
  void keep_chunk(int q, int chunks, const ContactConstraints& contacts, const Canvas& canvas, bool have_prev);
  /// Phase 3 over chunk q: its interior contacts without a colour take the lowest free one.
  void lowest_chunk(int q, int chunks, int nc, const Canvas& canvas);
  /// Throws for a contact naming a body outside `dynamic`; sums the tallies into out_.
  void finish(const ContactConstraints& contacts, int nb, int chunks);
  /// The table of this call's colours for the next call, and the repeat test's copy.
  void remember(const ContactConstraints& contacts, std::span<const std::uint8_t> dynamic);
  /// The contacts' (body_a, body_b, feature) and the flags equal the last call's.
  [[nodiscard]] bool same_as_last(const ContactConstraints& contacts, std::span<const std::uint8_t> dynamic) const;

  bool reuse_;
  int chunk_;
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
  // Parallel colouring: per chunk its body range, per body its shared mark, per chunk its
  // boundary contacts in contact order and its tally.
  std::vector<int> range_;
  std::vector<std::uint32_t> shared_;  // per body: stamp_ when shared in this call
  std::uint32_t stamp_ = 0;
  struct Pair {
    int a, b;  // a contact's dynamic bodies (body_a, body_b), −1 where none
  };
  std::vector<Pair> pair_;
  std::vector<int> bad_;  // per chunk: its first contact naming a body outside `dynamic`, or −1
  std::vector<std::vector<int>> boundary_;
  std::vector<Tally> tally_;
};

/// True when no two contacts of one colour (overflow excluded) share a body with dynamic[k] ≠ 0.
bool is_valid_coloring(const ContactConstraints& contacts, std::span<const std::uint8_t> dynamic,
                       const ContactColoring& coloring);

}  // namespace dc
