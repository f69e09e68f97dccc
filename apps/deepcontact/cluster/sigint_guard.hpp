#pragma once
// SIGINT handling for the long-running subcommands (generate, train): while a SigintGuard
// is alive, Ctrl-C only sets a flag that the command polls between units of work, so it can
// flush what is consistent and exit with a message saying how to resume. The flag is the
// CLI's one documented piece of global mutable state (a signal handler can touch nothing else).
#include <csignal>

namespace dc::cli {

/// True once SIGINT arrived while a SigintGuard was alive.
bool interrupted();

/// Installs the flag-setting SIGINT handler (clearing the flag) and restores the previous
/// disposition when destroyed. Across MPI ranks SIGTERM sets the flag too.
class SigintGuard {
 public:
  SigintGuard();
  ~SigintGuard();
  SigintGuard(const SigintGuard&) = delete;
  SigintGuard& operator=(const SigintGuard&) = delete;

 private:
  struct sigaction previous_ {};
  struct sigaction previous_term_ {};
  bool term_ = false;  ///< SIGTERM handled too (under MPI, see sigint_guard.cpp)
};

}  // namespace dc::cli
