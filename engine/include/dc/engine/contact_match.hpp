#pragma once
// Persistent-contact matching as one merge pass that hands each matched pair to the caller:
// match_contacts_by_key's pass without the index vector between the match and its use. A
// caller that reads the previous contact's fields (λ of the builtin warm start) reads them
// while that contact's key is in cache, instead of walking the previous list a second time
// (at tens of thousands of contacts both lists are far larger than the caches, and the walks
// over them are what the warm start costs).
#include <span>
#include <string>

#include "dc/core/error.hpp"
#include "dc/engine/contact.hpp"

namespace dc {

/// Calls f(c, previous[j]) for each contact c of `current` whose key is the key of previous[j],
/// in increasing c; the pairs match_contacts_by_key(previous, current) gives. Both lists must be
/// sorted by key; throws InvalidArgument naming the list (as match_contacts_by_key) if one is not,
/// possibly after calls of f for the contacts before the disorder.
template <class F>
void for_each_matched_contact(std::span<const Contact> previous, std::span<const Contact> current, F&& f) {
  // The sortedness checks ride along the merge pass, so each list is read once; every adjacent
  // pair of each list is still compared.
  const auto unsorted = [](const char* which) {
    return InvalidArgument(std::string("match_contacts_by_key: the ") + which + " contacts are not sorted by key");
  };
  std::size_t j = 0;
  const std::size_t np = previous.size();
  for (std::size_t c = 0; c < current.size(); ++c) {
    if (c > 0 && current[c].key < current[c - 1].key) throw unsorted("current");
    while (j < np && previous[j].key < current[c].key) {
      if (j + 1 < np && previous[j + 1].key < previous[j].key) throw unsorted("previous");
      ++j;
    }
    if (j < np && previous[j].key == current[c].key) f(c, previous[j]);
  }
  for (; j + 1 < np; ++j)
    if (previous[j + 1].key < previous[j].key) throw unsorted("previous");
}

}  // namespace dc
