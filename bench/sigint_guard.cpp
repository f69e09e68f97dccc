#include "sigint_guard.hpp"

namespace dc::cli {
namespace {

volatile std::sig_atomic_t g_interrupted = 0;

extern "C" void on_sigint(int) { g_interrupted = 1; }

}  // namespace

bool interrupted() { return g_interrupted != 0; }

SigintGuard::SigintGuard() {
  g_interrupted = 0;
  struct sigaction sa {};
  sa.sa_handler = on_sigint;
  sigemptyset(&sa.sa_mask);
  sa.sa_flags = 0;
  sigaction(SIGINT, &sa, &previous_);
}

SigintGuard::~SigintGuard() { sigaction(SIGINT, &previous_, nullptr); }

}  // namespace dc::cli
