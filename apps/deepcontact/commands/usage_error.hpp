#pragma once
// Usage errors in the house style: CLI11's parse errors ("The following argument was not
// expected: --stpes 3", "Value -3 not in range 0.000000 to 1797…") rewritten as one line that
// names the option, says what is allowed and suggests the closest option or subcommand.
// main() prints it after "deepcontact: error: " and exits with status 2 (docs/cli.md, "Exit
// status").
#include <string>
#include <vector>

namespace CLI {
class App;
class ParseError;
}  // namespace CLI

namespace dc::cli {

/// Exit status of a usage error (a wrong command line, as opposed to 1 for a failed run).
inline constexpr int kUsageExitStatus = 2;

/// The one-line message of a parse error of `app` for the command line `args` (argv[1..]).
std::string usage_error_message(const CLI::App& app, const CLI::ParseError& error, const std::vector<std::string>& args);

/// Lets every integer option of `app` and its subcommands take an exact integer in any numeric
/// notation ("--sweeps 1e3" = 1000); a value with a fraction ("2.5") stays an error. Call
/// after every option is added.
void accept_exact_integers(CLI::App& app);

/// The candidate closest to `word` by edit distance, or "" when none is close (more than a
/// third of the word's length, at least 2, edits away).
std::string closest_name(const std::string& word, const std::vector<std::string>& candidates);

}  // namespace dc::cli
