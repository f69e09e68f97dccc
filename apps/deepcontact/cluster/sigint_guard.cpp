#include "cluster/sigint_guard.hpp"

#include "cluster/comm.hpp"

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
  // An MPI job is stopped with SIGTERM (mpirun when a rank dies or on Ctrl-C, SLURM at the
  // time limit), then SIGKILL a little later: let the rank finish the append it is in.
  term_ = world().parallel();
  if (term_) sigaction(SIGTERM, &sa, &previous_term_);
}

SigintGuard::~SigintGuard() {
  sigaction(SIGINT, &previous_, nullptr);
  if (term_) sigaction(SIGTERM, &previous_term_, nullptr);
}

}  // namespace dc::cli
