#pragma once
// The SPH round-trip study (docs/sph.md "The round-trip study", `deepcontact sph-study`): how
// much of the solved contact forces survives particle → grid → particle over kernels, spacings
// d, supports h/d and normalisation modes — the ceiling of every grid-based warm start (sph,
// cnn). Each scene seed is simulated with its own solver; every setting splats all contacts
// of a step and reads them back at the contact points; the relative error |λ_rt − λ|₂ / |λ|₂ is
// collected over contacts with |λ_n| > min_lambda. run_sph_study computes; sph_study_csv /
// sph_study_markdown / write_sph_study / plot_sph_study write sph_study.csv (one row per
// setting), sph_study.md and the heat maps sph_study_<normalisation>.png (research/plots/sph_study.py).
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <string>
#include <string_view>
#include <vector>

#include "dc/engine/world_def.hpp"
#include "dc/sph/sph_kernel.hpp"
#include "dc/sph/sph_transfer.hpp"

namespace dc {

/// What the study simulates and which settings it measures (the defaults are sph-study's).
struct SphStudyDef {
  std::vector<std::uint64_t> seeds{1, 2};  ///< scene seeds (WorldDef::bodies.seed), one simulation each
  int steps = 0;                           ///< steps per simulation (≥ 0); 0 = the scene's [time] steps
  int every = 1;                           ///< sample every k-th step (≥ 1)
  int sweeps = 0;                          ///< solver sweeps per step (≥ 0); 0 = the scene's [solver] sweeps
  double min_lambda = 1e-2;                ///< [N] evaluate contacts with |λ_n| above this (finite, ≥ 0)
  std::vector<SphKernelType> kernels{SphKernelType::Poly6, SphKernelType::Spiky, SphKernelType::Cubic};
  std::vector<double> spacings{1, 0.5, 0.25};        ///< grid spacings d [m]
  std::vector<double> ratios{0.5, 0.71, 1, 1.5, 2};  ///< kernel supports h/d
  std::vector<SphNormalisation> normalisations{SphNormalisation::SumToOneLegacy, SphNormalisation::None,
                                               SphNormalisation::Shepard};
  /// ConfigError naming the sph-study option (every list non-empty, spacings and ratios > 0).
  void validate() const;
};

/// One transfer setting of the sweep.
struct SphStudySetting {
  SphKernelType kernel = SphKernelType::Poly6;
  double d = 0;      ///< grid spacing [m]
  double ratio = 0;  ///< support h = ratio·d
  SphNormalisation normalisation = SphNormalisation::Shepard;
};

/// The round-trip error of one setting over every evaluated contact of every frame.
struct SphStudyRow {
  SphStudySetting s;
  std::size_t contacts = 0;              ///< evaluated contacts (|λ_n| > min_lambda)
  double median = 0, p90 = 0, mean = 0;  ///< relative error |λ_rt − λ| / |λ|
  double median_n = 0;                   ///< median |λ_rt,n − λ_n| / |λ_n|
  double retained_n = 0;                 ///< median λ_rt,n / λ_n
  double unsupported = 0;                ///< share of evaluated contacts flagged unsupported (Shepard)
  double seconds = 0;                    ///< wall time of all round trips of this setting
};

struct SphStudyResults {
  SphStudyDef def;
  int steps = 0;                  ///< steps simulated per seed
  std::string solver;             ///< the scene's solver
  int sweeps = 0;                 ///< its sweeps per step
  std::size_t frames = 0;         ///< sampled steps with at least one contact, over all seeds
  std::size_t contacts = 0;       ///< contacts in those frames
  double simulation_seconds = 0;  ///< wall time of the simulations
  /// One per setting: normalisation-major, then kernel, spacing and ratio, in the def's order.
  std::vector<SphStudyRow> rows;
};

/// Called after each seed's simulation with its sampled frames and their contacts.
using SphStudySeedHook = std::function<void(std::uint64_t seed, std::size_t frames, std::size_t contacts)>;

/// Validates `def` and every grid on `scene`'s box, simulates `scene` once per seed (built-in
/// warm start: the study needs well-converged λ, not a solver benchmark) and measures every
/// setting. ConfigError when the simulations produce no contact, or no contact has
/// |λ_n| > min_lambda.
SphStudyResults run_sph_study(const WorldDef& scene, const SphStudyDef& def, const SphStudySeedHook& on_seed = {});

/// Relative errors below this are rounding (an exact round trip): the ranking treats them as equal.
inline constexpr double kSphStudyExact = 1e-9;

/// The study's ranking: median error, then mean error (both floored at kSphStudyExact: below it
/// the round trip is exact up to rounding and the digits are noise), then the coarsest grid
/// (largest d: fewest nodes, cheapest for a CNN), then the smallest support h/d.
bool sph_study_ranks_before(const SphStudyRow& a, const SphStudyRow& b);
/// The first row by that ranking (results with at least one row).
const SphStudyRow& best_sph_study_row(const SphStudyResults& r);
/// The legacy sum-to-one row at the seed setting (poly6, d = h = 0.5), or null when not measured.
const SphStudyRow* legacy_seed_row(const SphStudyResults& r);

/// sph_study.csv: a header and one line per row.
std::string sph_study_csv(const SphStudyResults& r);
/// sph_study.md. `scene` and `seeds` are how the report names them ("the seed scene" or
/// "`file.toml`"; the seed list as the user wrote it).
std::string sph_study_markdown(const SphStudyResults& r, std::string_view scene, std::string_view seeds);
/// Creates `dir` and writes sph_study.csv and sph_study.md into it (IoError on failure).
void write_sph_study(const SphStudyResults& r, const std::filesystem::path& dir, std::string_view scene,
                     std::string_view seeds);
/// Draws the heat maps of `dir`/sph_study.csv into `dir` with research/plots/sph_study.py (of
/// the source tree this was built from); the script's exit status (0 = drawn).
int plot_sph_study(const std::filesystem::path& dir);

/// "44.7 %", "2.0e-14 %", "0 %", "n/a": a relative error as the report and the CLI print it.
std::string sph_study_percent(double v);

}  // namespace dc
