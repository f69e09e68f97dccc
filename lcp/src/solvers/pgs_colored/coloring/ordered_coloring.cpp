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
  used_.assign(static_cast<size_t>(nb), 0);
  last_.assign(static_cast<size_t>(nb), -1);
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
    const int a = k.body_a >= 0 && dynamic[static_cast<size_t>(k.body_a)] != 0 ? k.body_a : -1;
    const int b = k.body_b >= 0 && dynamic[static_cast<size_t>(k.body_b)] != 0 ? k.body_b : -1;
    const int after = std::max(a >= 0 ? last_[static_cast<size_t>(a)] : -1, b >= 0 ? last_[static_cast<size_t>(b)] : -1);
    const std::uint64_t taken = (a >= 0 ? used_[static_cast<size_t>(a)] : 0) | (b >= 0 ? used_[static_cast<size_t>(b)] : 0);
    // The first free colour from (after + 1) mod K on: rotate the free mask so that bit 0 is it.
    const int from = (after + 1) % K;
    const std::uint64_t free = std::rotr(~taken, from);
    int colour = ContactColoring::kOverflow;
    if (free != 0) {
      colour = (from + std::countr_zero(free)) % K;
      const std::uint64_t bit = std::uint64_t{1} << colour;
      if (a >= 0) {
        used_[static_cast<size_t>(a)] |= bit;
        last_[static_cast<size_t>(a)] = static_cast<std::int8_t>(colour);
      }
      if (b >= 0) {
        used_[static_cast<size_t>(b)] |= bit;
        last_[static_cast<size_t>(b)] = static_cast<std::int8_t>(colour);
      }
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
