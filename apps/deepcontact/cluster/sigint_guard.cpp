#include "cluster/sigint_guard.hpp"

namespace dc::cli {
namespace {

/// The first stop signal that arrived (0: none). Written only by the handler.
volatile std::sig_atomic_t g_signal = 0;

extern "C" void on_stop_signal(int signal) {
  if (g_signal == 0) g_signal = signal;
}

}  // namespace

bool interrupted() { return g_signal != 0; }

int interrupt_exit_status() { return g_signal == SIGINT ? 130 : 143; }

const char* interrupt_signal_name() {
  switch (g_signal) {
    case SIGINT: return "SIGINT";
    case SIGTERM: return "SIGTERM";
    case SIGUSR1: return "SIGUSR1";
    default: return "";
  }
}

SigintGuard::SigintGuard() {
  g_signal = 0;
  struct sigaction sa {};
  sa.sa_handler = on_stop_signal;
  sigemptyset(&sa.sa_mask);
  sa.sa_flags = 0;
  for (int i = 0; i < 3; ++i) sigaction(kSignals[i], &sa, &previous_[i]);
}

SigintGuard::~SigintGuard() {
  for (int i = 0; i < 3; ++i) sigaction(kSignals[i], &previous_[i], nullptr);
}

}  // namespace dc::cli
