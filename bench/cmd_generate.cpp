// PLACEHOLDER until its issue lands: the subcommand exists but refuses to run.
#include <CLI/CLI.hpp>

#include "commands.hpp"
#include "dc/engine/error.hpp"

namespace dc::cli {
void add_generate_command(CLI::App& app) {
  auto* cmd = app.add_subcommand("generate", "(not yet implemented)");
  cmd->allow_extras();
  cmd->callback([] { throw dc::ConfigError("'generate' is not implemented yet"); });
}
}  // namespace dc::cli
