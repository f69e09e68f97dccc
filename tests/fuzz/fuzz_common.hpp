#pragma once
// Helpers shared by the libFuzzer harnesses (tests/fuzz/fuzz_*.cpp).
//
// Contract under test: a reader/parser fed arbitrary bytes either succeeds or throws one of
// the project's documented error types (dc::ConfigError, dc::IoError, dc::InvalidArgument).
// Anything else — a crash, a sanitizer report, a hang, another exception type escaping —
// is a finding. Harnesses therefore catch exactly those three types and let everything
// else propagate (libFuzzer reports an uncaught exception as a crash: "deadly signal").
#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>

namespace dc::fuzz {

/// A per-process temporary file for readers that need a path (HDF5): libFuzzer may run
/// several jobs at once (-jobs/-fork), so the name carries the pid. Removed at exit.
class TempInputFile {
 public:
  explicit TempInputFile(const char* suffix)
      : path_((std::filesystem::temp_directory_path() /
               ("dc_fuzz_" + std::to_string(::getpid()) + suffix)).string()) {}
  ~TempInputFile() { std::remove(path_.c_str()); }
  TempInputFile(const TempInputFile&) = delete;
  TempInputFile& operator=(const TempInputFile&) = delete;

  /// Replaces the file's content with the fuzzer's bytes; aborts if that fails (a broken
  /// harness must not look like a clean run).
  const std::string& write(const std::uint8_t* data, std::size_t size) {
    std::FILE* f = std::fopen(path_.c_str(), "wb");
    if (!f) std::abort();
    if (size > 0 && std::fwrite(data, 1, size, f) != size) std::abort();
    if (std::fclose(f) != 0) std::abort();
    return path_;
  }
  [[nodiscard]] const std::string& path() const { return path_; }

 private:
  std::string path_;
};

/// Stops the run with a message when a property the harness checks is violated.
[[noreturn]] inline void property_failed(const char* what) {
  std::fprintf(stderr, "fuzz property violated: %s\n", what);
  std::abort();
}

}  // namespace dc::fuzz
