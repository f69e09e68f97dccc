#pragma once
// The starters that answer research questions but are not methods: oracles, which read this
// step's tightly solved λ* (copy, copy:D, copy-noise:R, copy-range, copy-active[:F|:normal|
// :friction], copy-active-cg, sph, sph-residual, sph-gain, sph-gain-add: upper bounds of what a
// predictor could reach), and the negative controls random and bad. They are never in
// default_warm_starters(), the registry a user's own run draws from; the bench and the
// studies add them with add_research_starters().
#include <filesystem>
#include <string>
#include <vector>

#include "dc/warmstart/warm_starter.hpp"

namespace dc {

/// Adds the oracle starters and the negative controls to `registry`.
void add_research_starters(WarmStarterRegistry& registry);

/// Every starter the project has: default_warm_starters(), the cnn starters with `cnn_model`
/// as the default model (add_cnn_warm_starters), and add_research_starters(). What
/// `deepcontact bench`, the studies and the Python module draw from.
WarmStarterRegistry all_warm_starters(const std::filesystem::path& cnn_model);

/// The starters `deepcontact bench` runs when none are named: zero, builtin,
/// builtin-extrapolate, builtin-statics, copy, copy:2, copy:0, copy-noise:0.01, copy-noise:0.1,
/// sph, sph-prev, random, bad (quick: zero, builtin, copy, sph), plus cnn when `cnn_model`
/// exists.
std::vector<std::string> default_bench_starters(const std::filesystem::path& cnn_model, bool quick);

}  // namespace dc
