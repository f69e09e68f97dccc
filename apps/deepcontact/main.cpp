// deepcontact: the command-line front end. Thin subcommands over dc_engine, dc_warmstart
// and dc_learning; see `deepcontact --help` and docs/cli.md.
#include <CLI/CLI.hpp>
#include <csignal>
#include <cstdio>
#include <exception>
#include <new>
#include <string>
#include <vector>

#include "cluster/comm.hpp"
#include "commands/commands.hpp"
#include "commands/usage_error.hpp"
#include "dc/core/error.hpp"
#include "dc/core/install_paths.hpp"
#include "dc/io/h5.hpp"

namespace dc::cli {
int& exit_status() {
  static int status = 0;  // only main() and the one running subcommand touch it
  return status;
}
}  // namespace dc::cli

int main(int argc, char** argv) {
  dc::h5_skip_exit_cleanup();  // first: a file a failed write left open must not crash the exit (h5.hpp)
  // Past a file-size limit (ulimit -f) the kernel would kill us with SIGXFSZ mid-write; ignored,
  // the write fails with EFBIG instead and the error path reports it in one line and cleans up.
  std::signal(SIGXFSZ, SIG_IGN);
  const dc::cli::MpiSession mpi(argc, argv);  // MPI only under mpirun/srun (docs/cluster.md)
  CLI::App app{
      "DeepContact: how much can a warm start speed up the contact solver of a rigid-body "
      "simulator, and what does it cost?"};
  app.require_subcommand(1);
  app.set_version_flag("--version", "deepcontact " + dc::version() + " (commit " + dc::git_commit() + ")");
  dc::cli::add_simulate_command(app);
  dc::cli::add_lcp_command(app);
  dc::cli::add_bench_command(app);
  dc::cli::add_sph_study_command(app);
  dc::cli::add_pgs_landscape_command(app);
  dc::cli::add_generate_command(app);
  dc::cli::add_train_command(app);
  dc::cli::add_stress_command(app);
  dc::cli::add_render_command(app);
  dc::cli::accept_exact_integers(app);
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    if (e.get_exit_code() == 0) return app.exit(e);  // --help, --version
    // A wrong command line: one line with the closest option, exit status 2 (docs/cli.md).
    const std::vector<std::string> args(argv + 1, argv + argc);
    std::fprintf(stderr, "deepcontact: error: %s\n", dc::cli::usage_error_message(app, e, args).c_str());
    return dc::cli::kUsageExitStatus;
  } catch (const std::bad_alloc&) {
    std::fprintf(stderr, "deepcontact: error: out of memory\n");
    return 1;
  } catch (const std::exception& e) {
    const dc::cli::Comm& comm = dc::cli::world();
    if (!comm.parallel()) {
      std::fprintf(stderr, "deepcontact: error: %s\n", e.what());
      return 1;
    }
    // Across ranks the others may wait for this one in a collective: end the whole job (what
    // is on disk is consistent; generate and train resume from it).
    std::fprintf(stderr, "deepcontact: error: rank %d: %s\n", comm.rank(), e.what());
    comm.abort(1);
  }
  return dc::cli::exit_status();
}
