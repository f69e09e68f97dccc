#include <sstream>

#include "dc/core/error.hpp"
#include "dc/warmstart/warm_starter.hpp"

namespace dc {

WarmStartSpec WarmStartSpec::parse(const std::string& text) {
  WarmStartSpec s;
  const auto colon = text.find(':');
  s.name = text.substr(0, colon);
  if (colon != std::string::npos) s.arg = text.substr(colon + 1);
  if (s.name.empty()) throw ConfigError("warm starter: empty name in '" + text + "'");
  return s;
}

void WarmStarterRegistry::add(const std::string& name, std::string help, WarmStarterFactory factory) {
  if (name.empty() || name.find(':') != std::string::npos || name.find(',') != std::string::npos)
    throw InvalidArgument("warm starter name '" + name + "' must be non-empty without ':' or ','");
  if (!factory) throw InvalidArgument("warm starter '" + name + "': null factory");
  entries_[name] = Entry{std::move(help), std::move(factory)};
}

std::unique_ptr<WarmStarter> WarmStarterRegistry::make(const std::string& text,
                                                       const WarmStartEnv& env) const {
  const WarmStartSpec spec = WarmStartSpec::parse(text);
  const auto it = entries_.find(spec.name);
  if (it == entries_.end()) {
    std::ostringstream os;
    os << "unknown warm starter '" << spec.name << "' (available:";
    for (const auto& [n, e] : entries_) os << ' ' << n;
    os << ')';
    throw ConfigError(os.str());
  }
  if (env.registry) return it->second.factory(spec, env);
  WarmStartEnv with_registry = env;
  with_registry.registry = this;
  return it->second.factory(spec, with_registry);
}

std::vector<std::string> WarmStarterRegistry::names() const {
  std::vector<std::string> out;
  for (const auto& [n, e] : entries_) out.push_back(n);
  return out;
}

std::string WarmStarterRegistry::help() const {
  std::ostringstream os;
  for (const auto& [n, e] : entries_) os << "  " << n << ": " << e.help << '\n';
  return os.str();
}

}  // namespace dc
