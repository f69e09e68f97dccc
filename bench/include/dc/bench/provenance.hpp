#pragma once
// Reproducibility facts written into every report (docs/design.md §6): git revision, build type,
// compiler, machine, time.
#include <string>

namespace dc::bench {

struct Provenance {
  std::string git;        ///< the commit the binary was built from (dc::git_commit: 12 hex digits, "-dirty"), or "unknown"
  std::string build;      ///< CMake build type and compiler
  std::string machine;    ///< CPU model, logical cores
  std::string date_utc;   ///< ISO 8601
};

Provenance collect_provenance();

}  // namespace dc::bench
