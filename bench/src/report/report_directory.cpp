// The bench's output directory rule (report_directory.hpp).
#include "dc/bench/report_directory.hpp"

#include <algorithm>
#include <array>
#include <filesystem>
#include <string_view>

#include "dc/bench/bench_report.hpp"
#include "dc/core/error.hpp"
#include "dc/io/output_path.hpp"

namespace dc::bench {
namespace {

namespace fs = std::filesystem;

/// The file names (without the folder) of paths.
std::vector<std::string> names_of(const std::vector<std::string>& paths) {
  std::vector<std::string> names;
  for (const auto& p : paths) names.push_back(fs::path(p).filename().string());
  return names;
}

/// `text` with every `from` replaced by `to` (an error message naming the staging folder).
std::string replaced(std::string text, const std::string& from, std::string to) {
  while (to.size() > 1 && to.back() == '/') to.pop_back();
  for (std::size_t at = 0; (at = text.find(from, at)) != std::string::npos; at += to.size()) text.replace(at, from.size(), to);
  return text;
}

}  // namespace

bool is_report_file(const std::string& name) {
  static constexpr std::array<std::string_view, 17> kFiles = {
      "results.h5",      "summary.json",   "report.md",         "plots.log",         "intervals.png",
      "convergence.png", "pareto.png",     "sweeps_per_step.png", "time_breakdown.png", "accuracy.png",
      "reference.h5",    "reference_frame.png", "render.log",   "scale.csv",         "scale.json",
      "scale.png",       "scale.md"};
  if (std::find(kFiles.begin(), kFiles.end(), name) != kFiles.end()) return true;
  // A plot the script could not make leaves a note PLOT.na next to where PLOT.png would be.
  if (name.size() > 3 && name.compare(name.size() - 3, 3, ".na") == 0)
    return is_report_file(name.substr(0, name.size() - 3) + ".png");
  return name == "scale_plot.log";
}

void check_report_directory(const std::string& dir) { check_owned_directory(dir, is_report_file, "the bench"); }

std::string report_lock_target(const std::string& dir) {
  fs::path p = fs::absolute(dir).lexically_normal();
  if (!p.has_filename()) p = p.parent_path();  // "DIR/" and "." end in a separator
  return p.string();
}

std::vector<std::string> write_report_directory(const BenchResults& r, const std::string& dir) {
  std::vector<std::string> files;
  std::string incomplete;
  write_into_owned_directory(dir, is_report_file, [&](const std::string& staging) {
    try {
      files = names_of(write_report(r, staging));
    } catch (const IoError& e) {
      // The message names the file as it would have been in DIR.
      if (!fs::exists(fs::path(staging) / "report.md")) throw IoError(replaced(e.what(), staging, dir));
      incomplete = replaced(e.what(), staging, dir);  // report.md is written last
    }
  });
  if (!incomplete.empty()) throw IoError(incomplete);
  return files;
}

std::vector<std::string> write_scale_report_directory(const std::vector<ScalePoint>& points, ScaleAxis axis,
                                                      const std::string& dir) {
  std::vector<std::string> files;
  write_into_owned_directory(dir, is_report_file, [&](const std::string& staging) {
    try {
      files = names_of(write_scale_report(points, axis, staging));
    } catch (const IoError& e) {
      throw IoError(replaced(e.what(), staging, dir));
    }
  });
  return files;
}

}  // namespace dc::bench
