// The files of the SPH round-trip study (sph_study.hpp): sph_study.csv, sph_study.md and the
// heat maps drawn by research/plots/sph_study.py.
#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <iomanip>
#include <sstream>
#include <utility>

#include "dc/core/error.hpp"
#include "dc/io/atomic_file.hpp"
#include "dc/research/sph_study.hpp"
#include "dc/core/install_paths.hpp"

namespace dc {
namespace {

namespace fs = std::filesystem;

/// Shortest round-trip-ish text of a setting parameter (0.5, 0.71, 1).
std::string num(double v, int digits = 6) {
  std::ostringstream os;
  os << std::defaultfloat << std::setprecision(digits) << v;
  return os.str();
}

void write_introduction(std::ostream& md, const SphStudyResults& r, std::string_view scene, std::string_view seeds) {
  md << "# SPH round-trip study\n\n";
  md << "How much of the solved contact forces survives particle → grid → particle (docs/sph.md). "
        "Relative error |λ_rt − λ|₂ / |λ|₂ with λ = (λ_n, λ_t), over contacts with |λ_n| > "
     << r.def.min_lambda << " N.\n\n";
  md << "Scene: " << scene << ", seeds " << seeds << ", " << r.steps << " steps (sampling every k-th step, k = "
     << r.def.every << "), solver `" << r.solver << "` with " << r.sweeps << " sweeps (built-in warm start); "
     << r.frames << " frames, " << r.contacts << " contacts, " << r.rows.front().contacts
     << " evaluated per setting. "
     << "Simulation " << num(std::round(r.simulation_seconds * 10) / 10) << " s.\n\n"
     << "Shepard is exact (up to rounding) for every contact whose cell corners are reached by no other "
        "contact's kernel; its error grows with the overlap of supports (large h, coarse d). An exact round "
        "trip is necessary, not sufficient, for a learnable label grid: smoother fields (larger h) may be "
        "easier for a CNN to predict.\n\n";
}

/// The best setting overall, then the best of each normalisation.
void write_best_settings(std::ostream& md, const SphStudyResults& r) {
  const SphStudyRow& best = best_sph_study_row(r);
  const auto pct = sph_study_percent;
  md << "## Best setting\n\n";
  md << "**" << to_string(best.s.kernel) << ", d = " << num(best.s.d) << ", h = " << num(best.s.ratio) << "·d = "
     << num(best.s.ratio * best.s.d) << ", " << to_string(best.s.normalisation) << "**: median error "
     << pct(best.median) << ", 90th percentile " << pct(best.p90) << ", mean " << pct(best.mean)
     << ", median λ_n retained " << num(best.retained_n, 3) << ".\n\n"
     << "Ranking: median error, then mean error, both floored at " << kSphStudyExact
     << " (below it the round trip is exact up to rounding), then the coarsest grid, then the smallest h/d.\n\n";
  md << "| normalisation | best kernel | d | h/d | median error | p90 | median λ_n retained | unsupported |\n"
        "|---|---|---|---|---|---|---|---|\n";
  for (const auto norm : r.def.normalisations) {
    const SphStudyRow* b = nullptr;
    for (const SphStudyRow& row : r.rows)
      if (row.s.normalisation == norm && (!b || sph_study_ranks_before(row, *b))) b = &row;
    if (!b) continue;
    md << "| " << to_string(norm) << " | " << to_string(b->s.kernel) << " | " << num(b->s.d) << " | "
       << num(b->s.ratio) << " | " << pct(b->median) << " | " << pct(b->p90) << " | " << num(b->retained_n, 3)
       << " | " << pct(b->unsupported) << " |\n";
  }
}

/// The seed's own settings (poly6 at d = h = 0.5, spiky at d = h = 0.25) in every mode.
void write_seed_settings(std::ostream& md, const SphStudyResults& r) {
  const auto pct = sph_study_percent;
  md << "\n## The seed settings\n\n| setting | normalisation | median error | p90 | mean | median λ_n retained |"
        " unsupported |\n|---|---|---|---|---|---|---|\n";
  for (const auto& [kernel, d] : {std::pair{SphKernelType::Poly6, 0.5}, std::pair{SphKernelType::Spiky, 0.25}})
    for (const SphStudyRow& row : r.rows)
      if (row.s.kernel == kernel && row.s.d == d && row.s.ratio == 1.0)
        md << "| " << to_string(kernel) << ", d = h = " << num(d) << " | " << to_string(row.s.normalisation)
           << " | " << pct(row.median) << " | " << pct(row.p90) << " | " << pct(row.mean) << " | "
           << num(row.retained_n, 3) << " | " << pct(row.unsupported) << " |\n";
}

/// What the legacy sum-to-one weights lose, at the seed setting and over all its settings.
void write_legacy_loss(std::ostream& md, const SphStudyResults& r) {
  double lo = 1e300, hi = -1e300;
  for (const SphStudyRow& row : r.rows)
    if (row.s.normalisation == SphNormalisation::SumToOneLegacy) {
      lo = std::min(lo, row.retained_n);
      hi = std::max(hi, row.retained_n);
    }
  if (!(hi >= lo)) return;  // the legacy mode was not measured
  md << "\n## Legacy sum-to-one loss\n\n";
  if (const SphStudyRow* seed = legacy_seed_row(r))
    md << "At the seed setting (poly6, d = h = 0.5) the legacy mode returns a median " << num(seed->retained_n, 3)
       << " of λ_n (median error " << sph_study_percent(seed->median) << "). ";
  md << "Over all its settings the median retained λ_n ranges over " << num(lo, 3) << " … " << num(hi, 3) << ".\n";
}

/// Per normalisation, the median error of every (kernel, d) × h/d, and its heat map.
void write_error_tables(std::ostream& md, const SphStudyResults& r) {
  md << "\n## Median relative error per setting\n\n"
        "Rows: kernel and spacing d [m]; columns: h/d. h/d ≤ √2/2 ≈ 0.707 leaves points without kernel "
        "support (Shepard returns 0 there: see the unsupported share in the CSV).\n";
  for (const auto norm : r.def.normalisations) {
    md << "\n### " << to_string(norm) << "\n\n| kernel | d |";
    for (const double ratio : r.def.ratios) md << " h/d = " << num(ratio) << " |";
    md << "\n|---|---|";
    for (std::size_t k = 0; k < r.def.ratios.size(); ++k) md << "---|";
    md << '\n';
    for (const auto kernel : r.def.kernels)
      for (const double d : r.def.spacings) {
        md << "| " << to_string(kernel) << " | " << num(d) << " |";
        for (const double ratio : r.def.ratios)
          for (const SphStudyRow& row : r.rows)
            if (row.s.normalisation == norm && row.s.kernel == kernel && row.s.d == d && row.s.ratio == ratio)
              md << ' ' << sph_study_percent(row.median) << " |";
        md << '\n';
      }
    md << "\n![" << to_string(norm) << "](sph_study_" << to_string(norm) << ".png)\n";
  }
}

}  // namespace

std::string sph_study_percent(double v) {
  std::ostringstream os;
  if (!std::isfinite(v)) return "n/a";
  if (v == 0.0) return "0 %";
  if (v < 1e-4) os << std::scientific << std::setprecision(1) << 100 * v << " %";
  else os << std::fixed << std::setprecision(v < 0.1 ? 2 : 1) << 100 * v << " %";
  return os.str();
}

std::string sph_study_csv(const SphStudyResults& r) {
  std::ostringstream csv;
  csv << "kernel,d,h_over_d,h,normalisation,contacts,median_rel_error,p90_rel_error,mean_rel_error,"
         "median_rel_error_n,median_retained_n,unsupported_share,seconds\n";
  csv << std::setprecision(10);
  for (const SphStudyRow& row : r.rows)
    csv << to_string(row.s.kernel) << ',' << row.s.d << ',' << row.s.ratio << ',' << row.s.ratio * row.s.d << ','
        << to_string(row.s.normalisation) << ',' << row.contacts << ',' << row.median << ',' << row.p90 << ','
        << row.mean << ',' << row.median_n << ',' << row.retained_n << ',' << row.unsupported << ',' << row.seconds
        << '\n';
  return csv.str();
}

std::string sph_study_markdown(const SphStudyResults& r, std::string_view scene, std::string_view seeds) {
  if (r.rows.empty()) throw InvalidArgument("sph_study_markdown: the study has no rows");
  std::ostringstream md;
  write_introduction(md, r, scene, seeds);
  write_best_settings(md, r);
  write_seed_settings(md, r);
  write_legacy_loss(md, r);
  write_error_tables(md, r);
  return md.str();
}

void write_sph_study(const SphStudyResults& r, const fs::path& dir, std::string_view scene, std::string_view seeds) {
  std::error_code ec;
  fs::create_directories(dir, ec);
  if (ec) throw IoError(dir.string() + ": cannot create directory: " + ec.message());
  write_file_atomically((dir / "sph_study.csv").string(), sph_study_csv(r));
  write_file_atomically((dir / "sph_study.md").string(), sph_study_markdown(r, scene, seeds));
}

int plot_sph_study(const fs::path& dir) {
  const std::string script = data_path("research/plots/sph_study.py").string();
  const std::string py = fs::exists("/usr/bin/python3") ? "/usr/bin/python3" : "python3";
  const std::string cmd = py + " '" + script + "' '" + (dir / "sph_study.csv").string() + "' '" + dir.string() + "'";
  return std::system(cmd.c_str());
}

}  // namespace dc
