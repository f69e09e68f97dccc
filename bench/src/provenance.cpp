#include "dc/bench/provenance.hpp"

#include "dc/core/install_paths.hpp"

#include <cstdio>
#include <ctime>
#include <fstream>
#include <thread>

namespace dc::bench {

Provenance collect_provenance() {
  Provenance p;
  // The commit the binary was built from (taken at build time), not the state of some source
  // tree now: an installed or moved executable has none next to it.
  p.git = git_commit();
  p.build = std::string(DC_BUILD_TYPE) + ", " +
#if defined(__clang__)
            "clang " + std::to_string(__clang_major__) + "." + std::to_string(__clang_minor__);
#elif defined(__GNUC__)
            "g++ " + std::to_string(__GNUC__) + "." + std::to_string(__GNUC_MINOR__);
#else
            "unknown compiler";
#endif
  std::ifstream cpu("/proc/cpuinfo");
  std::string line, model = "unknown CPU";
  while (std::getline(cpu, line))
    if (line.rfind("model name", 0) == 0) {
      model = line.substr(line.find(':') + 2);
      break;
    }
  p.machine = model + ", " + std::to_string(std::thread::hardware_concurrency()) + " logical cores";
  const std::time_t t = std::time(nullptr);
  char buf[32];
  std::strftime(buf, sizeof buf, "%Y-%m-%dT%H:%M:%SZ", std::gmtime(&t));
  p.date_utc = buf;
  return p;
}

}  // namespace dc::bench
