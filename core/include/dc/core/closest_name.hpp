#pragma once
// "Did you mean …?": the candidate closest to a misspelt name, for one-line errors of the
// scene reader and of the command line alike.
#include <algorithm>
#include <cstddef>
#include <string>
#include <string_view>

namespace dc {

/// Levenshtein distance: the fewest insertions, deletions and substitutions of one character
/// that turn `a` into `b`.
std::size_t edit_distance(std::string_view a, std::string_view b);

/// The candidate closest to `word` if it is within max(2, |word|/3) edits, else "". Ties go
/// to the first candidate.
template <class Range>
std::string closest_name(std::string_view word, const Range& candidates) {
  std::string best;
  std::size_t best_d = std::max<std::size_t>(2, word.size() / 3) + 1;
  for (std::string_view c : candidates) {
    const std::size_t d = edit_distance(word, c);
    if (d < best_d) {
      best_d = d;
      best = std::string(c);
    }
  }
  return best;
}

}  // namespace dc
