#include "commands/usage_error.hpp"

#include <CLI/CLI.hpp>
#include <algorithm>
#include <cstdio>
#include <regex>
#include <sstream>

#include "dc/core/closest_name.hpp"

namespace dc::cli {
namespace {

/// The subcommands named on the command line, outermost first (app itself first).
std::vector<const CLI::App*> command_chain(const CLI::App& app, const std::vector<std::string>& args) {
  std::vector<const CLI::App*> chain{&app};
  for (const auto& word : args) {
    if (word.empty() || word[0] == '-') continue;
    for (const CLI::App* sub : chain.back()->get_subcommands([](const CLI::App*) { return true; }))
      if (sub->get_name() == word) {
        chain.push_back(sub);
        break;
      }
  }
  return chain;
}

std::string command_path(const std::vector<const CLI::App*>& chain) {
  std::string out = "deepcontact";
  for (std::size_t i = 1; i < chain.size(); ++i) out += " " + chain[i]->get_name();
  return out;
}

/// Every --long and -s name of the options of the innermost command (and --help).
std::vector<std::string> option_names(const CLI::App& cmd) {
  std::vector<std::string> out;
  for (const CLI::Option* opt : cmd.get_options()) {
    for (const auto& l : opt->get_lnames()) out.push_back("--" + l);
    for (const auto& s : opt->get_snames()) out.push_back("-" + s);
  }
  return out;
}

std::vector<std::string> subcommand_names(const CLI::App& cmd) {
  std::vector<std::string> out;
  for (const CLI::App* sub : cmd.get_subcommands([](const CLI::App*) { return true; })) out.push_back(sub->get_name());
  return out;
}

/// The message for one unexpected word: an unknown option, or a word that is no subcommand.
std::string unexpected_word(const std::string& word, const CLI::App& cmd) {
  const bool option = word.size() > 1 && word[0] == '-';
  const std::string name = option ? word.substr(0, word.find('=')) : word;
  const std::string hint = closest_name(name, option ? option_names(cmd) : subcommand_names(cmd));
  std::string msg = std::string(option ? "unknown option " : "unexpected argument ") + name;
  if (!hint.empty()) msg += "; did you mean " + hint + "?";
  else if (!option && !subcommand_names(cmd).empty()) msg += " (not a subcommand)";
  return msg;
}

/// "The following arguments were not expected: 3 --stpes" → "unknown option --stpes; did you
/// mean --steps?" (an option first: the value after it is only unexpected because of it).
std::string unexpected_arguments(const std::string& what, const CLI::App& cmd) {
  const auto colon = what.find(": ");
  std::istringstream words(colon == std::string::npos ? what : what.substr(colon + 2));
  std::vector<std::string> all;
  for (std::string word; words >> word;) all.push_back(word);
  for (const auto& word : all)
    if (word.size() > 1 && word[0] == '-') return unexpected_word(word, cmd);
  return all.empty() ? what : unexpected_word(all.front(), cmd);
}

/// The first word that is neither an option nor its value nor a known subcommand, when no
/// subcommand was recognised ("deepcontact simulat"): CLI11 only says one is required.
std::string unknown_subcommand(const CLI::App& app, const std::vector<std::string>& args) {
  for (const auto& word : args)
    if (!word.empty() && word[0] != '-') return unexpected_word(word, app);
  return "";
}

/// "Value -3 not in range 0.000000 to 1.797…e308" → "-3 is out of range: must be >= 0".
std::string range_message(const std::string& what) {
  static const std::regex range(R"(Value (\S+) not in range (\S+) to (\S+))");
  std::smatch m;
  if (!std::regex_search(what, m, range)) return what;
  const double lo = std::stod(m[2].str()), hi = std::stod(m[3].str());
  char bound[96];
  if (hi > 1e300) std::snprintf(bound, sizeof bound, "must be >= %g", lo);
  else std::snprintf(bound, sizeof bound, "must be between %g and %g", lo, hi);
  return m.prefix().str() + m[1].str() + " is out of range: " + bound + m.suffix().str();
}

}  // namespace

std::string closest_name(const std::string& word, const std::vector<std::string>& candidates) {
  return dc::closest_name(word, candidates);
}

std::string usage_error_message(const CLI::App& app, const CLI::ParseError& error, const std::vector<std::string>& args) {
  const auto chain = command_chain(app, args);
  const CLI::App& cmd = *chain.back();
  std::string what = error.what();
  // No subcommand recognised: the first word is the misspelt one, whatever CLI11 complained of.
  if (chain.size() == 1 && !unknown_subcommand(app, args).empty()) what = unknown_subcommand(app, args);
  else if (dynamic_cast<const CLI::ExtrasError*>(&error) != nullptr) what = unexpected_arguments(what, cmd);
  else what = range_message(what);
  return what + " (" + command_path(chain) + " --help)";
}

}  // namespace dc::cli
