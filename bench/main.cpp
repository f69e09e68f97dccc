// deepcontact: the command-line front end. Thin subcommands over dc_engine, dc_warmstart
// and dc_learning; see `deepcontact --help` and docs/cli.md.
#include <CLI/CLI.hpp>
#include <cstdio>
#include <exception>
#include <new>

#include "commands.hpp"
#include "dc/engine/error.hpp"

namespace dc::cli {
int& exit_status() {
  static int status = 0;  // only main() and the one running subcommand touch it
  return status;
}
}  // namespace dc::cli

int main(int argc, char** argv) {
  CLI::App app{
      "DeepContact: how much can a warm start speed up the contact solver of a rigid-body "
      "simulator, and what does it cost?"};
  app.require_subcommand(1);
  app.set_version_flag("--version", "deepcontact 0.1.0");
  dc::cli::add_simulate_command(app);
  dc::cli::add_lcp_command(app);
  dc::cli::add_bench_command(app);
  dc::cli::add_sph_study_command(app);
  dc::cli::add_generate_command(app);
  dc::cli::add_train_command(app);
  dc::cli::add_stress_command(app);
  dc::cli::add_render_command(app);
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e);  // usage errors: CLI11's message, exit status 105/106/...
  } catch (const std::bad_alloc&) {
    std::fprintf(stderr, "deepcontact: error: out of memory\n");
    return 1;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "deepcontact: error: %s\n", e.what());
    return 1;
  }
  return dc::cli::exit_status();
}
