#pragma once
// Helpers for tests that run the deepcontact executable (DC_CLI) as a child process.
#include <array>
#include <chrono>
#include <fstream>
#include <sstream>
#include <thread>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <csignal>
#include <string>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include "temp_dir.hpp"

namespace dc::test {

struct CliResult {
  int exit_code = -1;
  std::string out;  ///< stdout
  std::string err;  ///< stderr
};

/// Runs `DC_CLI <args>` through the shell, capturing stdout and stderr separately.
inline CliResult run_cli(const std::string& args) {
  const auto dir = std::filesystem::temp_directory_path();
  const std::string err_file = (dir / ("dc_cli_err_" + std::to_string(::getpid()) + ".txt")).string();
  const std::string cmd = std::string(DC_CLI) + " " + args + " 2>" + err_file;
  CliResult r;
  FILE* p = popen(cmd.c_str(), "r");
  if (!p) return r;
  std::array<char, 4096> buf{};
  std::size_t n;
  while ((n = fread(buf.data(), 1, buf.size(), p)) > 0) r.out.append(buf.data(), n);
  const int status = pclose(p);
  r.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
  if (FILE* e = std::fopen(err_file.c_str(), "r")) {
    while ((n = fread(buf.data(), 1, buf.size(), e)) > 0) r.err.append(buf.data(), n);
    std::fclose(e);
  }
  std::filesystem::remove(err_file);
  return r;
}

/// The bytes of a file ("" if it cannot be read).
inline std::string slurp_file(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

/// Runs `DC_CLI <args>` as run_cli() does, but in a child whose files may not grow past
/// `max_file_bytes` (setrlimit(RLIMIT_FSIZE)) and which ignores SIGXFSZ, so a write beyond
/// the limit fails with EFBIG as on a full disk instead of killing the process. stdout goes
/// to /dev/null (not limited); stderr is captured (it stays far below the limit). With
/// `ignore_sigxfsz` false the child keeps SIGXFSZ's default (kill): what a shell's `ulimit -f`
/// gives, so deepcontact must ignore the signal itself.
inline CliResult run_cli_with_file_limit(const std::string& args, std::size_t max_file_bytes,
                                         bool ignore_sigxfsz = true) {
  const auto dir = std::filesystem::temp_directory_path();
  const std::string err_file = (dir / ("dc_cli_fsize_err_" + std::to_string(::getpid()) + ".txt")).string();
  const std::string cmd = "exec " + std::string(DC_CLI) + " " + args + " >/dev/null 2>" + err_file;
  CliResult r;
  const pid_t pid = ::fork();
  if (pid < 0) return r;
  if (pid == 0) {
    const rlimit limit{static_cast<rlim_t>(max_file_bytes), static_cast<rlim_t>(max_file_bytes)};
    std::signal(SIGXFSZ, ignore_sigxfsz ? SIG_IGN : SIG_DFL);  // an ignored signal stays ignored across exec
    if (::setrlimit(RLIMIT_FSIZE, &limit) != 0) ::_exit(126);
    ::execl("/bin/sh", "sh", "-c", cmd.c_str(), static_cast<char*>(nullptr));
    ::_exit(127);
  }
  int status = 0;
  if (::waitpid(pid, &status, 0) != pid) return r;
  r.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
  r.err = slurp_file(err_file);
  std::filesystem::remove(err_file);
  return r;
}

/// The whole content of a text file ("" if it cannot be read).
inline std::string slurp(const std::string& path) { return slurp_file(path); }

/// What a background child's `log` file receives.
enum class ChildLog { StderrOnly, StdoutAndStderr };

/// Starts `DC_CLI ARGS` in the background (stdout to /dev/null unless logged); returns its pid.
inline pid_t spawn_cli(const std::string& args, const std::string& log, ChildLog what) {
  const std::string redirect =
      what == ChildLog::StderrOnly ? " >/dev/null 2>" + log : " >" + log + " 2>&1";
  const std::string cmd = "exec " + std::string(DC_CLI) + " " + args + redirect;
  const pid_t pid = ::fork();
  if (pid == 0) {
    ::execl("/bin/sh", "sh", "-c", cmd.c_str(), static_cast<char*>(nullptr));
    ::_exit(127);
  }
  return pid;
}

/// Waits until `log` contains `needle` (true) or the child exited / 60 s passed; a child that
/// exited is reaped here, so a later wait_exit() returns −2 for it.
inline bool wait_for(const std::string& log, const std::string& needle, pid_t pid) {
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(60);
  while (std::chrono::steady_clock::now() < deadline) {
    if (slurp(log).find(needle) != std::string::npos) return true;
    int st = 0;
    if (::waitpid(pid, &st, WNOHANG) == pid) return slurp(log).find(needle) != std::string::npos;
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  return false;
}

/// Waits until `path` exists (true) or the child exited / 60 s passed.
inline bool wait_for_file(const std::string& path, pid_t pid) {
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(60);
  while (std::chrono::steady_clock::now() < deadline) {
    if (std::filesystem::exists(path)) return true;
    if (::kill(pid, 0) != 0) return false;
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  return false;
}

/// Exit status of the child; −signal if it was killed, −2 if it was already reaped.
inline int wait_exit(pid_t pid) {
  int st = 0;
  if (::waitpid(pid, &st, 0) != pid) return -2;
  if (WIFSIGNALED(st)) return -WTERMSIG(st);
  return WIFEXITED(st) ? WEXITSTATUS(st) : -1;
}

inline int count_lines(const std::string& s) {
  int n = 0;
  for (char c : s) n += c == '\n';
  return n;
}

}  // namespace dc::test
