#pragma once
// Error types of the DeepContact libraries. Every user-facing failure is an exception
// whose what() is a single line that names the offending key, body, file or row, so the
// CLI can print it verbatim and exit non-zero. Validation never relies on assert().
#include <stdexcept>
#include <string>

namespace dc {

/// A scene, option or override is invalid (unknown key, wrong type, NaN, overlap, ...).
struct ConfigError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

/// A file could not be read or written, or its content is malformed/truncated.
struct IoError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

/// An argument handed to a library function violates its documented contract.
struct InvalidArgument : std::invalid_argument {
  using std::invalid_argument::invalid_argument;
};

}  // namespace dc
