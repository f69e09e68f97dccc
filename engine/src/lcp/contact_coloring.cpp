// Greedy, incremental colouring of contacts (contact_coloring.hpp).
#include "lcp/contact_coloring.hpp"

#include <algorithm>
#include <bit>
#include <string>

#include "dc/core/error.hpp"

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

const ContactColoring& ContactColorer::color(const ContactConstraints& contacts,
                                             std::span<const std::uint8_t> dynamic) {
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
  ++out_.generation;
  out_.color.assign(static_cast<size_t>(nc), ContactColoring::kOverflow);
  out_.colors = out_.reused = out_.overflow = 0;
  used_.assign(static_cast<size_t>(nb), 0);
  auto dyn = [&](int body) { return body >= 0 && dynamic[static_cast<size_t>(body)] != 0; };
  auto mask_of = [&](const ContactConstraint& k) {
    std::uint64_t m = 0;
    if (dyn(k.body_a)) m |= used_[static_cast<size_t>(k.body_a)];
    if (dyn(k.body_b)) m |= used_[static_cast<size_t>(k.body_b)];
    return m;
  };
  auto take = [&](int c, const ContactConstraint& k, int colour) {
    out_.color[static_cast<size_t>(c)] = colour;
    const std::uint64_t bit = std::uint64_t{1} << colour;
    if (dyn(k.body_a)) used_[static_cast<size_t>(k.body_a)] |= bit;
    if (dyn(k.body_b)) used_[static_cast<size_t>(k.body_b)] |= bit;
    out_.colors = std::max(out_.colors, colour + 1);
  };
  for (int c = 0; c < nc; ++c) {
    const ContactConstraint& k = contacts[c];
    if (k.body_b >= nb || k.body_a >= nb)
      throw InvalidArgument("contact colouring: contact " + std::to_string(c) + " names body " +
                            std::to_string(std::max(k.body_a, k.body_b)) + " of " + std::to_string(nb));
  }
  // 1. Persisting contacts keep last call's colour when it is still free on their bodies.
  const bool have_prev = reuse_ && !start_.empty();
  if (have_prev) {
    const int prev_bodies = static_cast<int>(start_.size()) - 1;
    for (int c = 0; c < nc; ++c) {
      const ContactConstraint& k = contacts[c];
      int first, other;
      identity(k, first, other);
      if (first >= prev_bodies) continue;
      for (int e = start_[static_cast<size_t>(first)]; e < start_[static_cast<size_t>(first) + 1]; ++e) {
        const Entry& en = entries_[static_cast<size_t>(e)];
        // Several contacts may share a key (two walls of one body have body_a = −1): each
        // takes the first matching entry whose colour is still free.
        if (en.other != other || en.feature != k.feature) continue;
        if (en.color != ContactColoring::kOverflow && ((mask_of(k) >> en.color) & 1) == 0) {
          take(c, k, en.color);
          ++out_.reused;
          break;
        }
      }
    }
  }
  // 2. The rest: the lowest colour free on both bodies, else the overflow set.
  for (int c = 0; c < nc; ++c) {
    if (have_prev && out_.color[static_cast<size_t>(c)] != ContactColoring::kOverflow) continue;
    const ContactConstraint& k = contacts[c];
    const std::uint64_t free = ~mask_of(k);
    if (free == 0) {
      ++out_.overflow;
      continue;
    }
    take(c, k, std::countr_zero(free));
  }
  // 3. Remember the colours by first body (counting sort) for the next call, and the contacts'
  // bodies and features and the flags for the repeat test.
  if (reuse_) {
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
  return out_;
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
