// The colouring in contact order of "pgs-colored" (ordered_coloring.hpp).
#include "solvers/pgs_colored/coloring/ordered_coloring.hpp"

#include <algorithm>
#include <bit>
#include <string>

#include "dc/core/error.hpp"

namespace dc::colored {

const ContactColoring& OrderedColorer::color(const ContactConstraints& contacts, std::span<const std::uint8_t> dynamic,
                                             const std::vector<int>& partner) {
  constexpr int K = ContactColoring::kMaxColors;
  static_assert(K == 64, "one bit per colour in a 64-bit mask");
  const int nc = contacts.size(), nb = static_cast<int>(dynamic.size());
  next_.resize(static_cast<size_t>(nc));
  // Each body's state in one 16-byte record (its colours, its latest colour, whether it is
  // dynamic): a contact reads two records, one cache line each, instead of three arrays per body.
  body_.resize(static_cast<size_t>(nb));
  for (int k = 0; k < nb; ++k) body_[static_cast<size_t>(k)] = BodyState{0, -1, dynamic[static_cast<size_t>(k)]};
  BodyState none{};  // an absent or static body: no colour taken, no latest colour, never written
  int colors = 0, overflow = 0;
  for (int c = 0; c < nc; ++c) {
    if (partner[static_cast<size_t>(c)] == -2) {  // a manifold's second point: its first point's lane
      next_[static_cast<size_t>(c)] = next_[static_cast<size_t>(c) - 1];
      continue;
    }
    const ContactConstraint& k = contacts[c];
    if (k.body_a >= nb || k.body_b >= nb)
      throw InvalidArgument("contact colouring: contact " + std::to_string(c) + " names body " +
                            std::to_string(std::max(k.body_a, k.body_b)) + " of " + std::to_string(nb));
    BodyState* a = k.body_a >= 0 ? &body_[static_cast<size_t>(k.body_a)] : &none;
    BodyState* b = k.body_b >= 0 ? &body_[static_cast<size_t>(k.body_b)] : &none;
    if (a->dynamic == 0) a = &none;
    if (b->dynamic == 0) b = &none;
    const int after = std::max<int>(a->last, b->last);
    const std::uint64_t taken = a->used | b->used;
    // The first free colour from (after + 1) mod K on: rotate the free mask so that bit 0 is it.
    const int from = (after + 1) % K;
    const std::uint64_t free = std::rotr(~taken, from);
    int colour = ContactColoring::kOverflow;
    if (free != 0) {
      colour = (from + std::countr_zero(free)) % K;
      const std::uint64_t bit = std::uint64_t{1} << colour;
      a->used |= bit;
      a->last = static_cast<std::int8_t>(colour);
      b->used |= bit;
      b->last = static_cast<std::int8_t>(colour);
      none = BodyState{};  // (written through a or b when one was absent or static)
      colors = std::max(colors, colour + 1);
    } else {
      ++overflow;
    }
    next_[static_cast<size_t>(c)] = colour;
  }
  out_.repeated = next_ == out_.color && colors == out_.colors && out_.generation != 0;
  if (!out_.repeated) {
    out_.color.swap(next_);
    ++out_.generation;
  }
  out_.colors = colors;
  out_.overflow = overflow;
  out_.reused = out_.repeated ? nc : 0;
  out_.chunks = 1;
  out_.boundary = 0;
  return out_;
}

}  // namespace dc::colored
