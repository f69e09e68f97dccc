#pragma once
// Stop signals for the long-running subcommands (generate, train, bench, simulate): while a
// SigintGuard is alive, SIGINT (Ctrl-C), SIGTERM (what batch systems send at the time limit
// and on scancel, and mpirun forwards) and SIGUSR1 (which batch systems can be told to send
// ahead of the limit, e.g. `sbatch --signal=USR1@120`) only set a flag that the command polls
// at its safe points (between steps, simulations, minibatches), so it can commit what is
// consistent, print one line and exit: 130 after SIGINT, 143 after SIGTERM or SIGUSR1 (the
// statuses of a shell whose child was killed by SIGINT / SIGTERM). The flag is the CLI's one
// documented piece of global mutable state (a signal handler can touch nothing else).
#include <csignal>

namespace dc::cli {

/// True once a stop signal arrived while a SigintGuard was alive.
bool interrupted();
/// The exit status for the signal that arrived: 130 (SIGINT) or 143 (SIGTERM, SIGUSR1).
int interrupt_exit_status();
/// "SIGINT", "SIGTERM" or "SIGUSR1" (the first that arrived); "" when none did.
const char* interrupt_signal_name();

/// Installs the flag-setting handler for SIGINT, SIGTERM and SIGUSR1 (clearing the flag) and
/// restores the previous dispositions when destroyed.
class SigintGuard {
 public:
  SigintGuard();
  ~SigintGuard();
  SigintGuard(const SigintGuard&) = delete;
  SigintGuard& operator=(const SigintGuard&) = delete;

 private:
  static constexpr int kSignals[3] = {SIGINT, SIGTERM, SIGUSR1};
  struct sigaction previous_[3] {};
};

}  // namespace dc::cli
