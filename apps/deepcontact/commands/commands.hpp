#pragma once
// Registration of the deepcontact subcommands. Each subcommand lives in its own cmd_*.cpp,
// parses its options with CLI11 and calls into the libraries; it reports failures by
// throwing (dc::ConfigError, dc::IoError, ...) and main() turns them into a one-line
// message and a non-zero exit status.
namespace CLI { class App; }

namespace dc::cli {

void add_simulate_command(CLI::App& app);   // cmd_simulate.cpp
void add_lcp_command(CLI::App& app);        // cmd_lcp.cpp       (lcp solve)
void add_bench_command(CLI::App& app);      // cmd_bench.cpp
void add_sph_study_command(CLI::App& app);  // cmd_sph_study.cpp
void add_pgs_landscape_command(CLI::App& app);  // cmd_pgs_landscape.cpp
void add_generate_command(CLI::App& app);   // cmd_generate.cpp
void add_train_command(CLI::App& app);      // cmd_train.cpp
void add_stress_command(CLI::App& app);     // cmd_stress.cpp
void add_render_command(CLI::App& app);     // cmd_render.cpp

/// Exit status a subcommand asks main() to return (0 = success). Set by commands whose
/// outcome is not an error but still not a success (e.g. `lcp solve` on an infeasible problem).
int& exit_status();

}  // namespace dc::cli
