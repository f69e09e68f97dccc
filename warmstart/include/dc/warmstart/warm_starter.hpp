#pragma once
// The WarmStarter abstraction (docs/design.md §4): given the step's contacts (with persistent keys),
// the body state and the assembled LCP, return an initial guess λ⁰ in the problem's row
// order; optionally observe the solved λ after the step. The caller times
// initial_guess(); a starter that needs the oracle λ* (copy, sph) reports the oracle's own
// cost separately via oracle_ms() so the bench can show it apart.
#include <Eigen/Core>
#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "dc/engine/world.hpp"

namespace dc {

/// What a warm starter sees in one step.
struct StepView {
  const World& world;  ///< bodies, contacts() of this step, previous_contacts(), problem()
  /// This step's tightly solved λ* when the caller already has it (the bench computes it
  /// once per step and shares it); nullptr ⇒ oracle starters solve it themselves.
  const Eigen::VectorXd* oracle = nullptr;
};

class WarmStarter {
 public:
  virtual ~WarmStarter() = default;
  /// Full name including options, e.g. "copy:2".
  [[nodiscard]] virtual std::string name() const = 0;
  /// λ⁰ for view.world.problem(); size = problem rows, finite, within the bounds' signs.
  virtual Eigen::VectorXd initial_guess(const StepView& view) = 0;
  /// initial_guess(view) into storage the caller keeps: `out` is resized to the problem's
  /// rows, its storage reused while they fit its capacity (a stepping loop that keeps `out`
  /// then allocates nothing for λ⁰, also while the row count changes). The same numbers as
  /// initial_guess(); this default copies initial_guess()'s vector into `out`, builtin writes
  /// in place.
  virtual void initial_guess_into(const StepView& view, KeptVector& out) { out = initial_guess(view); }
  /// Called after the step's solve with the solved λ (before integration).
  virtual void observe(const StepView& /*view*/, const Eigen::VectorXd& /*solved*/) {}
  /// True when the starter uses this step's solution (an oracle / upper bound, not a method).
  [[nodiscard]] virtual bool uses_oracle() const { return false; }
  /// Milliseconds the last initial_guess() spent computing the oracle itself (0 if shared).
  [[nodiscard]] virtual double oracle_ms() const { return 0.0; }
};

class WarmStarterRegistry;

/// Everything a factory may need to build a starter; the same for every starter of a run.
struct WarmStartEnv {
  std::uint64_t seed = 12345;   ///< seed for starters with randomness (random)
  std::string model_path;       ///< cnn: model file ("" = the shipped default)
  /// The registry a starter that wraps another one (gate:INNER) builds its inner starter
  /// from. WarmStarterRegistry::make sets it to itself when it is null; valid only during
  /// the factory call.
  const WarmStarterRegistry* registry = nullptr;
};

/// "name" or "name:arg" as written on the command line.
struct WarmStartSpec {
  std::string name;
  std::string arg;  ///< text after the first ':' ("" when none)
  static WarmStartSpec parse(const std::string& text);
  [[nodiscard]] std::string full() const { return arg.empty() ? name : name + ":" + arg; }
};

using WarmStarterFactory =
    std::function<std::unique_ptr<WarmStarter>(const WarmStartSpec&, const WarmStartEnv&)>;

/// Name → factory. Not global: build one (default_warm_starters()), add your own with
/// add(), and hand it to the bench. Unknown names are ConfigErrors listing the valid ones.
class WarmStarterRegistry {
 public:
  void add(const std::string& name, std::string help, WarmStarterFactory factory);
  [[nodiscard]] std::unique_ptr<WarmStarter> make(const std::string& text,
                                                  const WarmStartEnv& env = {}) const;
  [[nodiscard]] bool contains(const std::string& name) const { return entries_.count(name) > 0; }
  [[nodiscard]] std::vector<std::string> names() const;
  [[nodiscard]] std::string help() const;  ///< one line per starter

 private:
  struct Entry { std::string help; WarmStarterFactory factory; };
  std::map<std::string, Entry> entries_;
};

// project_feasible (clamp a guess into the bounds) is the engine's: dc/lcp/lcp_problem.hpp.

/// The registry with every starter of this library, the methods: zero, builtin,
/// builtin-extrapolate, builtin-statics, builtin-gain-extrapolate[:KERNEL:D:H[:NORM]],
/// builtin-coarse[:D[:ITER]], builtin-active, builtin-active-cg[:ITER], sph-prev[:KERNEL:D:H[:NORM]],
/// gate:INNER, gate-l2:INNER (options: starter_options.hpp). dc_cnn adds cnn and cnn-hybrid
/// (add_cnn_warm_starters), dc_research the oracles and controls (add_research_starters).
WarmStarterRegistry default_warm_starters();

/// True when `starter` is this library's `builtin` (default_warm_starters().make("builtin")):
/// its λ⁰ is, bit for bit, the engine's World::WarmStart::PreviousLambda and its observe() does
/// nothing, so a stepping loop may call World::step(solver, options,
/// World::WarmStart::PreviousLambda) instead, which under an engine-internal body order forms
/// λ⁰ in the internal rows without building the public views. A type test, not a virtual of
/// the interface: no other starter can claim it.
[[nodiscard]] bool is_builtin_warm_starter(const WarmStarter& starter);

/// The static load guess of builtin-statics for every contact of w's current step
/// (statics_warm_starter.cpp): bodies top-down, each body's weight plus the load resting on
/// it split over its upward-facing closing contacts; λ_n [N] (a force, like λ), λ_t = 0.
Eigen::VectorXd statics_guess(const World& w);

}  // namespace dc
