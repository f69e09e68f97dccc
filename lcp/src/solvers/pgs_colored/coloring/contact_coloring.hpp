#pragma once
// Greedy graph colouring of a step's contacts for the colour-ordered PGS ("pgs-colored",
// docs/design.md §8.4): no two contacts of one colour share a dynamic body, so a colour's
// contacts can be solved at the same time. Walls (body −1) and bodies with M⁻¹ = 0 do not
// conflict: the solver never writes them. A contact takes the lowest colour free on its
// bodies; with reuse, a persisting contact (key: lower body, other body, feature) keeps last
// call's colour when still free. Cost O(contacts + bodies): per-body bit masks and a counting
// sort by body, no hashing. At most kMaxColors colours, the rest go to the overflow set (run
// serially after the colours). A repeated contact set returns last call's result unchanged;
// the result never depends on the thread count. The repeat proof, the chunked four-phase rule
// and the choice of order: docs/lcp.md "Contact colouring: repeats and chunks".
#include <cstdint>
#include <span>
#include <vector>

#include "dc/lcp/contact_constraints.hpp"

namespace dc {

struct ContactColoring {
  static constexpr int kMaxColors = 64;
  static constexpr int kOverflow = -1;
  std::vector<int> color;  ///< per contact: 0..colors−1, or kOverflow
  int colors = 0;          ///< number of colours used (max colour + 1)
  int reused = 0;          ///< contacts that kept last call's colour
  int overflow = 0;        ///< contacts in the overflow set
  int chunks = 1;          ///< chunks coloured in parallel (docs/lcp.md "Contact colouring")
  int boundary = 0;        ///< contacts coloured serially after the chunks (phases 2 and 4)
  bool repeated = false;   ///< the contacts' bodies equal the last call's: colours unchanged
  /// Counts the calls whose colours were computed (not repeated): equal generations, same colours.
  std::uint64_t generation = 0;
};

class ContactColorer {
 public:
  /// Contacts per chunk of the parallel colouring (docs/lcp.md "Contact colouring: repeats
  /// and chunks"): large enough that the boundary contacts, coloured serially, are a small
  /// part of a body-ordered pile's contacts.
  static constexpr int kChunk = 4096;

  /// `reuse` = false colours every call from scratch (greedy in contact order); `chunk` = the
  /// contacts per chunk of the parallel colouring (≥ 1; small values are for tests; kChunk is
  /// the benchmarked choice), or 0 (the default) = always one chunk: the serial greedy rule, which
  /// on 2 threads still gives the faster sweeps (one colour fewer; docs/lcp.md "pgs-colored",
  /// "Alternatives considered"). Throws InvalidArgument for chunk < 0.
  explicit ContactColorer(bool reuse = true, int chunk = 0);

  /// Colours `contacts`; `dynamic[k]` says whether body k conflicts (size ≥ 1 + max body).
  /// `threads` (≥ 1) colour the chunks; the result is the same for every thread count.
  /// Throws InvalidArgument when a contact names a body outside `dynamic`.
  const ContactColoring& color(const ContactConstraints& contacts, std::span<const std::uint8_t> dynamic,
                               int threads = 1);

  /// The last call's result.
  [[nodiscard]] const ContactColoring& last() const { return out_; }
  /// Forgets the last call's colours (the next call colours from scratch).
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
