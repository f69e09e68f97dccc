#include "commands/usage_error.hpp"

#include <CLI/CLI.hpp>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
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

/// When `cmd` (the innermost command named, reached through `chain`) needs a subcommand and
/// none was recognised ("deepcontact simulat", "deepcontact lcp solv f"): the first word after
/// cmd's own name that is not an option, as an unknown subcommand with the closest name, or
/// the list of subcommands when there is no such word. CLI11 only says one is required.
std::string missing_subcommand(const std::vector<const CLI::App*>& chain, const std::vector<std::string>& args,
                               bool list_when_no_word) {
  const CLI::App& cmd = *chain.back();
  const std::vector<std::string> subs = subcommand_names(cmd);
  if (subs.empty()) return "";
  std::size_t from = 0;  // the word after the last recognised command name
  for (std::size_t c = 1; c < chain.size(); ++c)
    for (std::size_t i = from; i < args.size(); ++i)
      if (args[i] == chain[c]->get_name()) {
        from = i + 1;
        break;
      }
  for (std::size_t i = from; i < args.size(); ++i) {
    const std::string& word = args[i];
    if (word.empty() || word[0] == '-') continue;
    const std::string hint = closest_name(word, subs);
    return "unknown subcommand '" + word + "'" + (hint.empty() ? "" : "; did you mean '" + hint + "'?");
  }
  if (!list_when_no_word) return "";
  std::string list;
  for (std::size_t i = 0; i < subs.size(); ++i) list += (i == 0 ? "" : i + 1 == subs.size() ? " or " : ", ") + subs[i];
  return command_path(chain) + " needs a subcommand: " + list;
}

/// The option of `cmd` that `name` ("--steps") names, or nullptr.
const CLI::Option* find_option(const CLI::App& cmd, const std::string& name) {
  for (const CLI::Option* opt : cmd.get_options())
    for (const auto& l : opt->get_lnames())
      if ("--" + l == name) return opt;
  return nullptr;
}

/// true when `opt` takes an integer (CLI11's type name INT or UINT, possibly with a validator's
/// description after a colon).
bool takes_integer(const CLI::Option* opt) {
  if (opt == nullptr) return false;
  const std::string t = opt->get_type_name();
  return t.rfind("INT", 0) == 0 || t.rfind("UINT", 0) == 0;
}

/// "--steps: 'abc' is not an integer" (or "not a number" for a real-valued option), or "" when
/// `value` reads as a number of the option's type.
std::string not_a_number(const CLI::App& cmd, const std::string& option, const std::string& value) {
  const CLI::Option* opt = find_option(cmd, option);
  char* end = nullptr;
  const double v = std::strtod(value.c_str(), &end);
  const bool number = !value.empty() && end == value.c_str() + value.size();
  if (takes_integer(opt)) {
    if (!number) return option + ": '" + value + "' is not an integer";
    if (v != std::floor(v)) return option + ": " + value + " is not an integer";
    return option + ": " + value + " is out of range for an integer";
  }
  return number ? "" : option + ": '" + value + "' is not a number";
}

/// "Could not convert: --steps = 1e3x" → "--steps: '1e3x' is not an integer".
std::string conversion_message(const std::string& what, const CLI::App& cmd) {
  static const std::regex conv(R"(Could not convert: (\S+) = (.*))");
  std::smatch m;
  if (!std::regex_search(what, m, conv)) return what;
  const std::string said = not_a_number(cmd, m[1].str(), m[2].str());
  return said.empty() ? what : said;
}

/// "--steps: Value -3 not in range 0.000000 to 1.797…e308" → "--steps: -3 is out of range:
/// must be >= 0"; a value that is no number at all ("abc") → "--steps: 'abc' is not an integer".
std::string range_message(const std::string& what, const CLI::App& cmd) {
  static const std::regex range(R"(Value (\S+) not in range (\S+) to (\S+))");
  std::smatch m;
  if (!std::regex_search(what, m, range)) return what;
  const std::string option = m.prefix().str().substr(0, m.prefix().str().find(':'));
  char* end = nullptr;
  const std::string value = m[1].str();
  std::strtod(value.c_str(), &end);
  if (value.empty() || end != value.c_str() + value.size()) {
    const std::string said = not_a_number(cmd, option, value);
    if (!said.empty()) return said;
    return option + ": '" + value + "' is not a number";
  }
  const double lo = std::stod(m[2].str()), hi = std::stod(m[3].str());
  char bound[96];
  if (hi > 1e300) std::snprintf(bound, sizeof bound, "must be >= %g", lo);
  else std::snprintf(bound, sizeof bound, "must be between %g and %g", lo, hi);
  return m.prefix().str() + m[1].str() + " is out of range: " + bound + m.suffix().str();
}

/// An integer option's value written as an exact integer in another notation ("1e3", "1000.0")
/// → its digits ("1000"); anything else unchanged (CLI11 then reports what is wrong with it).
std::string exact_integer_digits(std::string value) {
  if (value.find_first_of(".eE") == std::string::npos) return value;
  char* end = nullptr;
  const double v = std::strtod(value.c_str(), &end);
  if (value.empty() || end != value.c_str() + value.size() || !std::isfinite(v) || v != std::floor(v) ||
      std::fabs(v) > 9007199254740992.0)  // 2^53: every integer below is exact in a double
    return value;
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.0f", v);
  return buf;
}

void add_integer_transforms(CLI::App& cmd) {
  for (CLI::Option* opt : cmd.get_options())
    if (takes_integer(opt)) opt->transform(exact_integer_digits, "", "");
  for (CLI::App* sub : cmd.get_subcommands([](CLI::App*) { return true; })) add_integer_transforms(*sub);
}

}  // namespace

void accept_exact_integers(CLI::App& app) { add_integer_transforms(app); }

std::string closest_name(const std::string& word, const std::vector<std::string>& candidates) {
  return dc::closest_name(word, candidates);
}

std::string usage_error_message(const CLI::App& app, const CLI::ParseError& error, const std::vector<std::string>& args) {
  const auto chain = command_chain(app, args);
  const CLI::App& cmd = *chain.back();
  std::string what = error.what();
  // A command that needs a subcommand got none it knows: the first word after it is the misspelt
  // one, whatever CLI11 complained of.
  const bool needs_sub = cmd.get_require_subcommand_min() > 0 || chain.size() == 1;
  const bool none_given = what.find("subcommand is required") != std::string::npos;
  const std::string sub = needs_sub ? missing_subcommand(chain, args, none_given) : "";
  if (!sub.empty()) what = sub;
  else if (dynamic_cast<const CLI::ExtrasError*>(&error) != nullptr) what = unexpected_arguments(what, cmd);
  else if (dynamic_cast<const CLI::ConversionError*>(&error) != nullptr) what = conversion_message(what, cmd);
  else what = range_message(what, cmd);
  return what + " (" + command_path(chain) + " --help)";
}

}  // namespace dc::cli
