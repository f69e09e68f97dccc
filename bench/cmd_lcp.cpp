// PLACEHOLDER until its issue lands: the subcommand exists but refuses to run.
#include <CLI/CLI.hpp>

#include "commands.hpp"
#include "dc/engine/error.hpp"

namespace dc::cli {
void add_lcp_command(CLI::App& app) {
  auto* cmd = app.add_subcommand("lcp", "(not yet implemented)");
  cmd->allow_extras();
  cmd->callback([] { throw dc::ConfigError("'lcp' is not implemented yet"); });
}
}  // namespace dc::cli
