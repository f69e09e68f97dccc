#pragma once
// Reproducibility facts written into every report (DESIGN §6): git revision, build type,
// compiler, machine, time.
#include <string>

namespace dc::bench {

struct Provenance {
  std::string git;        ///< `git rev-parse HEAD` of the source tree (+ "-dirty"), or "unknown"
  std::string build;      ///< CMake build type and compiler
  std::string machine;    ///< CPU model, logical cores
  std::string date_utc;   ///< ISO 8601
};

Provenance collect_provenance();

/// Minimal JSON string escaping (quotes, backslash, control characters).
std::string json_escape(const std::string& s);
/// A double as JSON: full precision, NaN/Inf as null.
std::string json_number(double v);

}  // namespace dc::bench
