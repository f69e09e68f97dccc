#include <filesystem>

#include "dc/cnn/cnn_warm_starter.hpp"
#include "dc/research/research_starters.hpp"

namespace dc {

WarmStarterRegistry all_warm_starters(const std::filesystem::path& cnn_model) {
  WarmStarterRegistry r = default_warm_starters();
  add_cnn_warm_starters(r, cnn_model);
  add_research_starters(r);
  return r;
}

std::vector<std::string> default_bench_starters(const std::filesystem::path& cnn_model, bool quick) {
  std::vector<std::string> out = {"zero",    "builtin",  "builtin-extrapolate", "builtin-statics", "copy",
                                  "copy:2",  "copy:0",   "copy-noise:0.01",     "copy-noise:0.1",  "sph",
                                  "sph-prev", "random",  "bad"};
  if (quick) out = {"zero", "builtin", "copy", "sph"};
  // cnn only when the shipped model is there (a checkout without it still benches the rest;
  // `--warmstarts cnn --model F` selects another model explicitly).
  if (std::filesystem::exists(cnn_model)) out.push_back("cnn");
  return out;
}

}  // namespace dc
