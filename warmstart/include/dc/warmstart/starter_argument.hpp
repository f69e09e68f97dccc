#pragma once
// The shared parsers a starter's options are built on (starter_options.hpp, dc_research's
// oracle_starter_options.hpp, dc_cnn's cnn_starter_options.hpp; a user's starter may use them).
// A starter is named "NAME" or "NAME:ARG" (WarmStartSpec), ARG holding ':'-separated fields.
// Every failure is one ConfigError naming the whole spec and the expected form:
//     warm starter 'builtin-coarse:x': expected builtin-coarse[:D[:ITER]] with D > 0 [m] and ITER >= 1
// Numbers follow std::stoi / std::stod / std::stoull: leading white space skipped, no trailing
// text, values the type cannot hold refused ("copy:+3", "builtin-coarse:0x1p0",
// "copy-noise:1e-2" are accepted).
#include <cstddef>
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

#include "dc/warmstart/warm_starter.hpp"

namespace dc {

/// A starter's argument together with the form it should have, for the error messages.
class StarterArgument {
 public:
  /// `usage` is what follows "expected " in the message: the starter's forms and the ranges of
  /// its fields, e.g. "copy[:D] with D an integer in 0..15".
  StarterArgument(const WarmStartSpec& spec, std::string usage);

  [[nodiscard]] bool empty() const { return spec_.arg.empty(); }
  [[nodiscard]] const std::string& text() const { return spec_.arg; }
  [[nodiscard]] const WarmStartSpec& spec() const { return spec_; }

  /// The ':'-separated fields of the argument: none when it is empty, empty fields kept ("1:"
  /// is {"1", ""}, which no number parser accepts). ConfigError unless the count is in
  /// [min_fields, max_fields].
  [[nodiscard]] std::vector<std::string> fields(std::size_t min_fields, std::size_t max_fields) const;

  /// An integer in [lo, hi] (std::stoi rules).
  [[nodiscard]] int integer(const std::string& field, int lo, int hi = std::numeric_limits<int>::max()) const;
  /// A finite number > 0 (std::stod rules): lengths, spacings.
  [[nodiscard]] double positive_number(const std::string& field) const;
  /// A finite number in [lo, hi] (std::stod rules); hi = +∞ accepts every finite number ≥ lo.
  [[nodiscard]] double number(const std::string& field, double lo, double hi) const;
  /// An unsigned 64-bit integer (std::stoull rules, so "-1" wraps to 2⁶⁴ − 1).
  [[nodiscard]] std::uint64_t unsigned_integer(const std::string& field) const;

  /// ConfigError "warm starter 'SPEC': expected USAGE".
  [[noreturn]] void fail() const;
  /// ConfigError "warm starter 'SPEC': expected USAGE (REASON)", e.g. the SPH setting's own
  /// message naming the bad part.
  [[noreturn]] void fail(const std::string& reason) const;

 private:
  WarmStartSpec spec_;
  std::string usage_;
};

/// ConfigError "warm starter 'NAME:ARG': expected NAME without an argument" unless the spec has
/// no ":ARG" part: the check of every starter that takes no argument (zero, builtin, bad, …).
void reject_argument(const WarmStartSpec& spec);

}  // namespace dc
