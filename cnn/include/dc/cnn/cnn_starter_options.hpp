#pragma once
// The options of the learned starters, "cnn[:PATH]" and "cnn-hybrid[:PATH]", parsed in this one
// place like the methods' (dc/warmstart/starter_options.hpp); docs/bench.md "Starters and their
// arguments" lists the same forms. PATH is any text (a file name may hold ':'): a missing or
// unreadable model is an IoError when the starter loads it, not a parse error.
#include <filesystem>

#include "dc/warmstart/warm_starter.hpp"

namespace dc {

/// cnn[:PATH], cnn-hybrid[:PATH] (cnn_warm_starter.hpp).
struct CnnStarterOptions {
  /// PATH: the model file. Empty: WarmStartEnv::model_path (`bench --model`), else the default
  /// model the registry was given (add_cnn_warm_starters; the CLI's is the shipped models/default.h5).
  std::filesystem::path model;
  /// cnn-hybrid: builtin for persistent contacts, the network only for new ones (the name says it).
  bool hybrid = false;
};

/// The model path from the argument and `hybrid` from the name. InvalidArgument when spec.name
/// is neither "cnn" nor "cnn-hybrid" (a factory registered under another name).
CnnStarterOptions parse_cnn_options(const WarmStartSpec& spec);

/// The model file a starter with these options loads: options.model, else env.model_path, else
/// `default_model`.
std::filesystem::path cnn_model_path(const CnnStarterOptions& options, const WarmStartEnv& env,
                                     const std::filesystem::path& default_model);

}  // namespace dc
