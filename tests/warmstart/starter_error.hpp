#pragma once
// The shape every refused starter argument must have: one ConfigError of one line that names
// the whole spec and says what was expected ("warm starter 'copy:x': expected copy[:D] …"), so
// a mistyped --warmstarts item points at itself and at its fix.
#include <gtest/gtest.h>

#include <string>

#include "dc/core/error.hpp"
#include "dc/warmstart/warm_starter.hpp"

namespace dc::test {

/// The message of the ConfigError `f` throws ("" and a test failure when it throws none).
template <class F>
std::string config_error_of(F&& f) {
  try {
    f();
  } catch (const ConfigError& e) {
    return e.what();
  }
  ADD_FAILURE() << "no ConfigError";
  return "";
}

/// One line, starting "warm starter 'SPEC': expected " and containing `usage`.
inline void expect_starter_error(const std::string& message, const std::string& spec, const std::string& usage) {
  EXPECT_EQ(message.find('\n'), std::string::npos) << message;
  EXPECT_EQ(message.rfind("warm starter '" + spec + "': expected ", 0), 0u) << spec << " -> " << message;
  EXPECT_NE(message.find(usage), std::string::npos) << spec << " -> " << message;
}

/// The spec as the command line writes it.
inline WarmStartSpec spec(const std::string& text) { return WarmStartSpec::parse(text); }

/// Expects `parse(spec(text))` to refuse `text` with the uniform message containing `usage`.
template <class Parse>
void expect_refused(Parse parse, const std::string& text, const std::string& usage) {
  const WarmStartSpec s = spec(text);
  expect_starter_error(config_error_of([&] { (void)parse(s); }), s.full(), usage);
}

/// Every starter of `r` but the gates (whose argument is another starter, with its own check)
/// refuses the malformed argument ":1:2:3:4:5" with the uniform message: each factory is seen
/// to go through its parser.
inline void expect_every_starter_refuses_a_malformed_argument(const WarmStarterRegistry& r) {
  for (const std::string& name : r.names()) {
    if (name == "gate" || name == "gate-l2") continue;
    const std::string bad = name + ":1:2:3:4:5";
    expect_starter_error(config_error_of([&] { (void)r.make(bad); }), bad, name);
  }
}

}  // namespace dc::test
