#pragma once
// Registration of the deepcontact subcommands. Each subcommand lives in its own NAME_command.cpp,
// parses its options with CLI11 and calls into the libraries; it reports failures by
// throwing (dc::ConfigError, dc::IoError, ...) and main() turns them into a one-line
// message and a non-zero exit status.
namespace CLI { class App; }

namespace dc::cli {

void add_simulate_command(CLI::App& app);   // simulate_command.cpp
void add_lcp_command(CLI::App& app);        // lcp_command.cpp       (lcp solve)
void add_bench_command(CLI::App& app);      // bench_command.cpp
void add_sph_study_command(CLI::App& app);  // sph_study_command.cpp
void add_pgs_landscape_command(CLI::App& app);  // pgs_landscape_command.cpp
void add_generate_command(CLI::App& app);   // generate_command.cpp
void add_train_command(CLI::App& app);      // train_command.cpp
void add_stress_command(CLI::App& app);     // stress_command.cpp
void add_render_command(CLI::App& app);     // render_command.cpp

/// Exit status a subcommand asks main() to return (0 = success). Set by commands whose
/// outcome is not an error but still not a success (e.g. `lcp solve` on an infeasible problem).
int& exit_status();

}  // namespace dc::cli
