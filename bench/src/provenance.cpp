#include "dc/bench/provenance.hpp"

#include <array>
#include <cstdio>
#include <ctime>
#include <fstream>
#include <memory>
#include <thread>

namespace dc::bench {
namespace {

std::string run(const std::string& cmd) {
  std::array<char, 256> buf{};
  std::string out;
  std::unique_ptr<FILE, int (*)(FILE*)> p(popen(cmd.c_str(), "r"), pclose);
  if (!p) return {};
  while (fgets(buf.data(), buf.size(), p.get())) out += buf.data();
  while (!out.empty() && (out.back() == '\n' || out.back() == '\r')) out.pop_back();
  return out;
}

}  // namespace

Provenance collect_provenance() {
  Provenance p;
  const std::string src = DC_SOURCE_DIR;
  p.git = run("git -C '" + src + "' rev-parse --short=12 HEAD 2>/dev/null");
  if (p.git.empty()) {
    p.git = "unknown";
  } else if (!run("git -C '" + src + "' status --porcelain --untracked-files=no 2>/dev/null").empty()) {
    p.git += "-dirty";
  }
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
