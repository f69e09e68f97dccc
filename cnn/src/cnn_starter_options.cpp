#include "dc/cnn/cnn_starter_options.hpp"

#include <string>

#include "dc/core/error.hpp"

namespace dc {

CnnStarterOptions parse_cnn_options(const WarmStartSpec& spec) {
  CnnStarterOptions o;
  if (spec.name == "cnn-hybrid") o.hybrid = true;
  else if (spec.name != "cnn") throw InvalidArgument("parse_cnn_options: '" + spec.name + "' is not cnn or cnn-hybrid");
  o.model = spec.arg;
  return o;
}

std::filesystem::path cnn_model_path(const CnnStarterOptions& options, const WarmStartEnv& env,
                                     const std::filesystem::path& default_model) {
  if (!options.model.empty()) return options.model;
  if (!env.model_path.empty()) return env.model_path;
  return default_model;
}

}  // namespace dc
