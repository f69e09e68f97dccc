// Greedy, incremental colouring of contacts (contact_coloring.hpp).
#include "solvers/pgs_colored/coloring/contact_coloring.hpp"

#include <algorithm>
#include <atomic>
#include <bit>
#include <string>

#include "dc/core/error.hpp"
#include "dc/core/work_team.hpp"

namespace dc {
namespace {

/// (first, other): the lower body first, or (body_b, −1) for a wall contact.
void identity(const ContactConstraint& k, int& first, int& other) {
  if (k.has_body_a()) {
    first = std::min(k.body_a, k.body_b);
    other = std::max(k.body_a, k.body_b);
  } else {
    first = k.body_b;
    other = -1;
  }
}

}  // namespace

void ContactColorer::reset() {
  start_.clear();
  entries_.clear();
  repeatable_ = false;
}

bool ContactColorer::same_as_last(const ContactConstraints& contacts, std::span<const std::uint8_t> dynamic) const {
  const int nc = contacts.size();
  if (static_cast<size_t>(nc) != last_keys_.size() || dynamic.size() != last_dynamic_.size()) return false;
  if (!std::equal(dynamic.begin(), dynamic.end(), last_dynamic_.begin())) return false;
  // Field by field, without early exit (a branch-free AND over the contacts).
  bool same = true;
  const Key* last = last_keys_.data();
  for (int c = 0; c < nc; ++c) {
    const ContactConstraint& k = contacts[c];
    same &= (k.body_a == last[c].body_a) & (k.body_b == last[c].body_b) & (k.feature == last[c].feature);
  }
  return same;
}

ContactColorer::ContactColorer(bool reuse, int chunk) : reuse_(reuse), chunk_(chunk) {
  if (chunk < 0) throw InvalidArgument("contact colouring: chunk size " + std::to_string(chunk) + " is negative");
}

struct ContactColorer::Canvas {
  const Pair* pair;     // per contact: its dynamic bodies (−1: none)
  std::uint64_t* used;  // per body: bit c set when colour c holds one of its contacts
  int* color;           // per contact
  std::uint32_t* shared;  // per body: this call's stamp when a contact of a chunk not owning its range touches it
  const int* start;     // last call's table (start_, entries_); prev_bodies = 0: none
  const Entry* entries;
  int prev_bodies;

  /// OR of the used-colour masks of contact c's dynamic bodies.
  [[nodiscard]] std::uint64_t mask_of(int c) const {
    const Pair p = pair[c];
    return (p.a >= 0 ? used[p.a] : 0) | (p.b >= 0 ? used[p.b] : 0);
  }
  /// Gives contact c colour `colour` and marks it on its dynamic bodies.
  void take(int c, int colour, Tally& t) const {
    color[c] = colour;
    const std::uint64_t bit = std::uint64_t{1} << colour;
    const Pair p = pair[c];
    if (p.a >= 0) used[p.a] |= bit;
    if (p.b >= 0) used[p.b] |= bit;
    t.colors = std::max(t.colors, colour + 1);
  }
  /// Reuse (phases 1, 2): contact c takes the colour of the first entry of last call with its
  /// key whose colour is free on its bodies.
  void keep_last(int c, const ContactConstraint& k, Tally& t) const {
    int first, other;
    identity(k, first, other);
    if (first >= prev_bodies) return;
    for (int e = start[first]; e < start[first + 1]; ++e) {
      const Entry& en = entries[e];
      // Several contacts may share a key (two walls of one body have body_a = −1): each
      // takes the first matching entry whose colour is still free.
      if (en.other != other || en.feature != k.feature || en.color == ContactColoring::kOverflow) continue;
      if (((mask_of(c) >> en.color) & 1) == 0) {
        take(c, en.color, t);
        ++t.reused;
        return;
      }
    }
  }
  /// Phases 3, 4: the lowest colour free on c's bodies, else the overflow set.
  void take_lowest(int c, Tally& t) const {
    if (color[c] != ContactColoring::kOverflow) return;  // kept its colour
    const std::uint64_t free = ~mask_of(c);
    if (free == 0) {
      ++t.overflow;
      return;
    }
    take(c, std::countr_zero(free), t);
  }
};

const ContactColoring& ContactColorer::color(const ContactConstraints& contacts,
                                             std::span<const std::uint8_t> dynamic, int threads) {
  const int nc = contacts.size();
  const int nb = static_cast<int>(dynamic.size());
  if (reuse_ && repeatable_ && same_as_last(contacts, dynamic)) {
    // Every contact keeps its colour (see the header): the result is last call's, as is the
    // table for the next call.
    out_.reused = nc;
    out_.repeated = true;
    return out_;
  }
  out_.repeated = false;
  repeatable_ = false;  // until this call completes
  const bool have_prev = reuse_ && !start_.empty();
  const int chunks = prepare(contacts, nb);
  threads = chunks > 1 ? std::clamp(threads, 1, chunks) : 1;
  const Canvas canvas{pair_.data(),  used_.data(),    out_.color.data(),
                      shared_.data(), start_.data(), entries_.data(),
                      have_prev ? static_cast<int>(start_.size()) - 1 : 0};
  const std::uint8_t* dyn = dynamic.data();
  Tally& serial = tally_[static_cast<size_t>(chunks)];
  // The contacts are read from their 32-byte records once (pass 0) and then from the 8-byte
  // pairs: the passes are bound by memory traffic.
  if (threads <= 1) {
    // The phases below in order, without a parallel region (libgomp allocates a team even for
    // a region that runs serially, and a work-share for an orphaned dynamic loop).
    for (int b = 0; b < nb; ++b) canvas.used[b] = 0;
    for (int q = 0; q < chunks; ++q) pair_chunk(q, chunks, contacts, dyn, nb, canvas);
    for (int q = 0; q < chunks; ++q) keep_chunk(q, chunks, contacts, canvas, have_prev);
    if (have_prev)
      for (int q = 0; q < chunks; ++q)
        for (const int c : boundary_[static_cast<size_t>(q)]) canvas.keep_last(c, contacts[c], serial);
    if (have_prev || chunks == 1)
      for (int q = 0; q < chunks; ++q) lowest_chunk(q, chunks, nc, canvas);
    for (int q = 0; q < chunks; ++q)
      for (const int c : boundary_[static_cast<size_t>(q)]) canvas.take_lowest(c, serial);
  } else {  // the same phases, the chunks of a phase on the calling thread's team
    WorkTeam& team = calling_thread_team();
    std::fill(canvas.used, canvas.used + nb, std::uint64_t{0});
    team.for_parts(threads, chunks, [&](int q) { pair_chunk(q, chunks, contacts, dyn, nb, canvas); });
    // (A contact naming a body outside `dynamic` has no bodies in its pair, and keep_last
    // reads only last call's table: the phases below run safely, and the call throws after.)
    team.for_parts(threads, chunks, [&](int q) { keep_chunk(q, chunks, contacts, canvas, have_prev); });
    // Phase 2 (serial, contact order): the boundary contacts keep their colour where free.
    if (have_prev)
      for (int q = 0; q < chunks; ++q)
        for (const int c : boundary_[static_cast<size_t>(q)]) canvas.keep_last(c, contacts[c], serial);
    // Phase 3: the other interior contacts take the lowest free colour (done in phase 1 when
    // colouring from scratch with several chunks).
    if (have_prev || chunks == 1)
      team.for_parts(threads, chunks, [&](int q) { lowest_chunk(q, chunks, nc, canvas); });
    // Phase 4 (serial, contact order): the other boundary contacts.
    for (int q = 0; q < chunks; ++q)
      for (const int c : boundary_[static_cast<size_t>(q)]) canvas.take_lowest(c, serial);
  }
  finish(contacts, nb, chunks);
  if (reuse_) remember(contacts, dynamic);
  return out_;
}

int ContactColorer::prepare(const ContactConstraints& contacts, int nb) {
  const int nc = contacts.size();
  const int chunks = chunk_ == 0 ? 1 : std::max(1, nc / chunk_);  // 0: one chunk, the serial rule
  out_.color.resize(static_cast<size_t>(nc));
  used_.resize(static_cast<size_t>(nb));
  pair_.resize(static_cast<size_t>(nc));
  tally_.assign(static_cast<size_t>(chunks) + 1, Tally{});  // the last: the serial phases
  bad_.assign(static_cast<size_t>(chunks), -1);
  if (static_cast<int>(boundary_.size()) < chunks) boundary_.resize(static_cast<size_t>(chunks));
  if (chunks > 1) {
    // Chunk q owns the bodies from the first body of its first contact (kept ascending) to the
    // next chunk's: disjoint ranges, a function of the contacts only.
    range_.resize(static_cast<size_t>(chunks) + 1);
    range_[0] = 0;
    for (int q = 1; q < chunks; ++q) {
      int first, other;
      identity(contacts[chunk_begin(q, chunks, nc)], first, other);
      range_[static_cast<size_t>(q)] = std::clamp(first, range_[static_cast<size_t>(q) - 1], nb);
    }
    range_[static_cast<size_t>(chunks)] = nb;
    // The shared marks carry the call's stamp, so they need no clearing between calls.
    if (++stamp_ == 0) {
      std::fill(shared_.begin(), shared_.end(), 0u);
      stamp_ = 1;
    }
    shared_.resize(static_cast<size_t>(nb), 0u);
  }
  return chunks;
}

// A contact's dynamic body outside its chunk's range is touched by two chunks (its range's
// owner may touch it as well, and cannot tell): shared. The marks are one value stored by any
// number of writers, so the end state does not depend on the threads. (Relaxed atomic stores:
// plain moves on x86-64.)
void ContactColorer::pair_chunk(int q, int chunks, const ContactConstraints& contacts, const std::uint8_t* dyn,
                                int nb, const Canvas& canvas) {
  const int nc = contacts.size();
  const int lo = chunk_begin(q, chunks, nc), hi = chunk_begin(q + 1, chunks, nc);
  const ContactConstraint* k = contacts.contacts().data();
  int* color = canvas.color;
  Pair* pair = pair_.data();
  std::uint32_t* shared = canvas.shared;
  const std::uint32_t stamp = stamp_;
  const bool chunked = chunks > 1;
  const int r0 = chunked ? range_[static_cast<size_t>(q)] : 0, r1 = chunked ? range_[static_cast<size_t>(q) + 1] : 0;
  int first_bad = -1;
  for (int c = lo; c < hi; ++c) {
    color[c] = ContactColoring::kOverflow;
    const int ka = k[c].body_a, kb = k[c].body_b;
    if (kb >= nb || ka >= nb) {
      if (first_bad < 0) first_bad = c;
      pair[c] = {-1, -1};
      continue;
    }
    const int a = ka >= 0 && dyn[ka] != 0 ? ka : -1;
    const int b = kb >= 0 && dyn[kb] != 0 ? kb : -1;
    pair[c] = {a, b};
    if (chunked) {
      if (a >= 0 && (a < r0 || a >= r1)) std::atomic_ref<std::uint32_t>(shared[a]).store(stamp, std::memory_order_relaxed);
      if (b >= 0 && (b < r0 || b >= r1)) std::atomic_ref<std::uint32_t>(shared[b]).store(stamp, std::memory_order_relaxed);
    }
  }
  bad_[static_cast<size_t>(q)] = first_bad;
}

void ContactColorer::keep_chunk(int q, int chunks, const ContactConstraints& contacts, const Canvas& canvas,
                                bool have_prev) {
  const int nc = contacts.size();
  const int lo = chunk_begin(q, chunks, nc), hi = chunk_begin(q + 1, chunks, nc);
  std::vector<int>& edge = boundary_[static_cast<size_t>(q)];
  edge.clear();
  // Local copies (registers: no reloads through memory the stores might alias).
  const Canvas cv = canvas;
  Tally t = tally_[static_cast<size_t>(q)];
  if (chunks > 1) {
    // Private: in [r0, r1) and not shared; as one unsigned compare per body.
    const unsigned r0 = static_cast<unsigned>(range_[static_cast<size_t>(q)]);
    const unsigned width = static_cast<unsigned>(range_[static_cast<size_t>(q) + 1]) - r0;
    const std::uint32_t* shared = cv.shared;
    const std::uint32_t stamp = stamp_;
    const Pair* pair = cv.pair;
    auto is_private = [&](int body) {
      return body < 0 || (static_cast<unsigned>(body) - r0 < width && shared[body] != stamp);
    };
    for (int c = lo; c < hi; ++c) {
      if (!(is_private(pair[c].a) && is_private(pair[c].b))) {
        edge.push_back(c);
      } else if (have_prev) {
        cv.keep_last(c, contacts[c], t);
      } else {
        cv.take_lowest(c, t);  // phase 3 at once: without reuse phase 2 does nothing
      }
    }
  } else if (have_prev) {
    for (int c = lo; c < hi; ++c) cv.keep_last(c, contacts[c], t);
  }
  tally_[static_cast<size_t>(q)] = t;
}

void ContactColorer::lowest_chunk(int q, int chunks, int nc, const Canvas& canvas) {
  const int lo = chunk_begin(q, chunks, nc), hi = chunk_begin(q + 1, chunks, nc);
  const Canvas cv = canvas;
  Tally t = tally_[static_cast<size_t>(q)];
  // Between the chunk's boundary contacts (phase 4's), in contact order.
  const std::vector<int>& edge = boundary_[static_cast<size_t>(q)];
  int from = lo;
  for (size_t e = 0; e <= edge.size(); ++e) {
    const int to = e < edge.size() ? edge[e] : hi;
    for (int c = from; c < to; ++c) cv.take_lowest(c, t);
    from = to + 1;
  }
  tally_[static_cast<size_t>(q)] = t;
}

void ContactColorer::finish(const ContactConstraints& contacts, int nb, int chunks) {
  for (const int c : bad_)
    if (c >= 0) {
      const ContactConstraint& k = contacts[c];
      throw InvalidArgument("contact colouring: contact " + std::to_string(c) + " names body " +
                            std::to_string(std::max(k.body_a, k.body_b)) + " of " + std::to_string(nb));
    }
  ++out_.generation;
  out_.chunks = chunks;
  out_.colors = out_.reused = out_.overflow = out_.boundary = 0;
  for (int q = 0; q <= chunks; ++q) {
    const Tally& t = tally_[static_cast<size_t>(q)];
    out_.colors = std::max(out_.colors, t.colors);
    out_.reused += t.reused;
    out_.overflow += t.overflow;
    if (q < chunks && chunks > 1) out_.boundary += static_cast<int>(boundary_[static_cast<size_t>(q)].size());
  }
}

void ContactColorer::remember(const ContactConstraints& contacts, std::span<const std::uint8_t> dynamic) {
  // The colours by first body (counting sort) for the next call, and the contacts' bodies and
  // features and the flags for the repeat test.
  const int nc = contacts.size(), nb = static_cast<int>(dynamic.size());
  start_.assign(static_cast<size_t>(nb) + 1, 0);
  for (int c = 0; c < nc; ++c) {
    int first, other;
    identity(contacts[c], first, other);
    ++start_[static_cast<size_t>(first) + 1];
  }
  for (int k = 0; k < nb; ++k) start_[static_cast<size_t>(k) + 1] += start_[static_cast<size_t>(k)];
  entries_.resize(static_cast<size_t>(nc));
  last_keys_.resize(static_cast<size_t>(nc));
  std::vector<int>& fill = scratch_;
  fill.assign(start_.begin(), start_.end() - 1);
  bool each_has_a_dynamic_body = true;
  auto dyn = [&](int body) { return body >= 0 && dynamic[static_cast<size_t>(body)] != 0; };
  for (int c = 0; c < nc; ++c) {
    const ContactConstraint& k = contacts[c];
    int first, other;
    identity(k, first, other);
    entries_[static_cast<size_t>(fill[static_cast<size_t>(first)]++)] = {other, k.feature,
                                                                         out_.color[static_cast<size_t>(c)]};
    last_keys_[static_cast<size_t>(c)] = {k.body_a, k.body_b, k.feature};
    each_has_a_dynamic_body &= dyn(k.body_a) || dyn(k.body_b);
  }
  last_dynamic_.assign(dynamic.begin(), dynamic.end());
  repeatable_ = out_.overflow == 0 && each_has_a_dynamic_body;
}

bool is_valid_coloring(const ContactConstraints& contacts, std::span<const std::uint8_t> dynamic,
                       const ContactColoring& coloring) {
  if (static_cast<int>(coloring.color.size()) != contacts.size()) return false;
  // seen[body] = 1 + the last colour slot that holds the body, per colour: a colour-major scan.
  std::vector<std::vector<int>> by_color(static_cast<size_t>(std::max(coloring.colors, 0)));
  for (int c = 0; c < contacts.size(); ++c) {
    const int col = coloring.color[static_cast<size_t>(c)];
    if (col == ContactColoring::kOverflow) continue;
    if (col < 0 || col >= coloring.colors) return false;
    by_color[static_cast<size_t>(col)].push_back(c);
  }
  std::vector<int> mark(dynamic.size(), -1);
  for (int col = 0; col < coloring.colors; ++col) {
    for (int c : by_color[static_cast<size_t>(col)]) {
      for (int body : {contacts[c].body_a, contacts[c].body_b}) {
        if (body < 0 || static_cast<size_t>(body) >= dynamic.size() || !dynamic[static_cast<size_t>(body)]) continue;
        if (mark[static_cast<size_t>(body)] == col) return false;
        mark[static_cast<size_t>(body)] = col;
      }
    }
  }
  return true;
}

}  // namespace dc
