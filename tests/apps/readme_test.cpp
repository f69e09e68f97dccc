// The README's lists cannot drift from the code: its command table names exactly the
// subcommands of `deepcontact --help`, its layout table every top-level folder of code, and its
// two starter lists exactly the methods (default_warm_starters() plus the cnn starters) and the
// research starters (add_research_starters()). Each list sits between HTML comment markers.
#include <gtest/gtest.h>

#include <filesystem>
#include <regex>
#include <set>
#include <sstream>
#include <string>

#include "cli_helpers.hpp"
#include "dc/cnn/cnn_warm_starter.hpp"
#include "dc/research/research_starters.hpp"

namespace dc {
namespace {

namespace fs = std::filesystem;

/// The README's text between `<!-- NAME` and `<!-- /NAME -->`.
std::string readme_section(const std::string& name) {
  const std::string text = test::slurp_file(std::string(DC_SOURCE_DIR) + "/README.md");
  const auto begin = text.find("<!-- " + name);
  const auto end = text.find("<!-- /" + name + " -->");
  if (begin == std::string::npos || end == std::string::npos || end < begin) {
    ADD_FAILURE() << "README.md has no section '" << name << "'";
    return {};
  }
  return text.substr(begin, end - begin);
}

/// Every match of group 1 of `pattern` in `text`.
std::set<std::string> matches(const std::string& text, const std::string& pattern) {
  std::set<std::string> out;
  const std::regex re(pattern);
  for (auto it = std::sregex_iterator(text.begin(), text.end(), re); it != std::sregex_iterator(); ++it)
    out.insert((*it)[1].str());
  return out;
}

/// The starter names of a list section: every `name` before the " — " of a bullet.
std::set<std::string> listed_starters(const std::string& section) {
  std::set<std::string> out;
  std::istringstream in(readme_section(section));
  for (std::string line; std::getline(in, line);) {
    if (line.rfind("- ", 0) != 0) continue;
    const std::string names = line.substr(0, line.find(" — "));
    for (const auto& n : matches(names, "`([a-z0-9-]+)`")) out.insert(n);
  }
  return out;
}

std::set<std::string> names_of(const WarmStarterRegistry& r) {
  const auto v = r.names();
  return {v.begin(), v.end()};
}

TEST(Readme, CommandTableNamesEverySubcommand) {
  const test::CliResult help = test::run_cli("--help");
  ASSERT_EQ(help.exit_code, 0) << help.err;
  const std::string subcommands = help.out.substr(help.out.find("Subcommands:"));
  const std::set<std::string> actual = matches(subcommands, "\n  ([a-z][a-z0-9-]*) ");
  ASSERT_FALSE(actual.empty()) << help.out;
  EXPECT_EQ(matches(readme_section("commands"), "\\| `deepcontact ([a-z][a-z0-9-]*)"), actual);
}

TEST(Readme, LayoutTableNamesEveryFolderOfCode) {
  const std::set<std::string> listed = matches(readme_section("layout"), "\n\\| `([a-z][a-z0-9_-]*)/`");
  ASSERT_FALSE(listed.empty());
  for (const auto& dir : listed) EXPECT_TRUE(fs::is_directory(fs::path(DC_SOURCE_DIR) / dir)) << dir << "/ is listed but missing";
  // Every top-level folder with code (a CMakeLists.txt, or under apps/) is in the table.
  for (const auto& e : fs::directory_iterator(DC_SOURCE_DIR)) {
    const std::string name = e.path().filename().string();
    if (!e.is_directory() || name.empty() || name[0] == '.') continue;
    if (fs::exists(e.path() / "CMakeLists.txt")) { EXPECT_TRUE(listed.count(name)) << name << "/ is missing from the layout"; }
  }
  for (const char* dir : {"apps", "tests", "scripts", "docs", "python"}) EXPECT_TRUE(listed.count(dir)) << dir;
}

TEST(Readme, StarterListsAreTheRegistries) {
  WarmStarterRegistry methods = default_warm_starters();
  add_cnn_warm_starters(methods, std::filesystem::path(DC_SOURCE_DIR) / "models" / "default.h5");
  const std::set<std::string> method_names = names_of(methods);
  WarmStarterRegistry research;
  add_research_starters(research);
  EXPECT_EQ(listed_starters("starters:methods"), method_names);
  EXPECT_EQ(listed_starters("starters:research"), names_of(research));
}

}  // namespace
}  // namespace dc
