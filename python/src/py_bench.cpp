// deepcontact.bench(): the warm-start benchmark of `deepcontact bench`, with warm starters
// given by name or as Python objects; returns the content of summary.json as a dict.
#include <pybind11/stl.h>

#include <fstream>
#include <optional>
#include <set>
#include <sstream>

#include "dc/bench/bench_report.hpp"
#include "dc/bench/bench_runner.hpp"
#include "dc/bench/bench_statistics.hpp"
#include "dc/bench/bench_summary.hpp"
#include "dc/bench/list_options.hpp"
#include "dc/bench/progress_bar.hpp"
#include "dc/bench/provenance.hpp"
#include "dc/bench/report_directory.hpp"
#include "dc/core/error.hpp"
#include "dc/io/output_lock.hpp"
#include "py_common.hpp"

namespace dc::py {
namespace {

std::vector<std::uint64_t> seeds_from_python(pyb::handle seeds) {
  if (pyb::isinstance<pyb::str>(seeds)) return bench::parse_seed_range(seeds.cast<std::string>());
  if (pyb::isinstance<pyb::int_>(seeds)) return {seeds.cast<std::uint64_t>()};
  std::vector<std::uint64_t> out;
  for (auto s : seeds) {
    if (s.cast<long long>() < 0) throw ConfigError("--seeds: seeds must be non-negative integers");
    out.push_back(s.cast<std::uint64_t>());
  }
  if (out.empty()) throw ConfigError("--seeds: no seeds given");
  return out;
}

pyb::object bench(pyb::object scene, pyb::object set, pyb::object warmstarts, pyb::object seeds, bool quick,
                  const std::string& mode, pyb::object out, pyb::object sweeps, double tol, const std::string& solver,
                  pyb::object steps, const std::string& model, bool progress, pyb::object solvers, double accuracy,
                  int jobs) {
  WarmStarterRegistry registry = user_registry();
  bench::BenchOptions o;
  o.scene = scene_from_python(scene, set);
  o.seeds = seeds.is_none() ? std::vector<std::uint64_t>{1} : seeds_from_python(seeds);
  if (!steps.is_none()) o.scene.time.steps = steps.cast<int>();
  o.sweeps = sweeps.is_none() ? o.scene.solver.sweeps : sweeps.cast<int>();
  o.tolerance = tol;
  o.solver = SolverId::parse(solver);
  o.env.model_path = model;
  if (!solvers.is_none()) {
    if (pyb::isinstance<pyb::str>(solvers)) throw pyb::type_error("solvers: a list of solver names, e.g. ['pgs', 'nncg']");
    for (auto s : solvers) o.solvers.push_back(SolverId::parse(s.cast<std::string>()));
    if (o.solvers.empty()) throw ConfigError("bench: solvers is empty (None turns the solver comparison off)");
  }
  o.accuracy = accuracy;
  o.jobs = jobs;
  if (mode == "paired") o.mode = bench::Mode::Paired;
  else if (mode == "rollout") o.mode = bench::Mode::Rollout;
  else throw ConfigError("--mode must be 'paired' or 'rollout', got '" + mode + "'");

  // Python starters get registry entries of their own; a class (or a factory without
  // initial_guess) is called once per seed, like the C++ factories; an instance is shared.
  pyb::list items;  // keeps every object alive for the run
  if (warmstarts.is_none()) {
    for (const auto& n : default_python_bench_starters(quick)) items.append(pyb::str(n));
  } else {
    for (auto w : warmstarts) items.append(w);
  }
  std::set<std::string> names;
  for (std::size_t i = 0; i < items.size(); ++i) {
    pyb::handle w = items[i];
    std::string spec;
    if (pyb::isinstance<pyb::str>(w)) {
      spec = w.cast<std::string>();
    } else {
      const bool factory = pyb::isinstance<pyb::type>(w) || !pyb::hasattr(w, "initial_guess");
      if (factory && !PyCallable_Check(w.ptr()))
        throw pyb::type_error("warmstarts: " + pyb::repr(w).cast<std::string>() +
                              " is neither a name, a warm starter nor a class/factory of one");
      spec = "python-starter-" + std::to_string(i);
      registry.add(spec, "Python warm starter", [w, factory](const WarmStartSpec&, const WarmStartEnv&) {
        pyb::gil_scoped_acquire gil;
        if (!factory) return make_python_warm_starter(w);
        pyb::object made = pyb::reinterpret_borrow<pyb::object>(w)();
        return make_python_warm_starter(made);
      });
    }
    const std::string name = registry.make(spec, o.env)->name();
    if (!names.insert(name).second) throw ConfigError("bench: warm starter '" + name + "' is listed twice");
    o.warmstarts.push_back(spec);
  }

  const bool to_dir = !out.is_none();
  const std::string dir = to_dir ? pyb::str(pyb::module_::import("os").attr("fspath")(out)).cast<std::string>() : "";
  // The same rule as `bench --out DIR` (report_directory.hpp): checked and locked before the run.
  if (to_dir) bench::check_report_directory(dir);
  std::optional<OutputLock> lock;
  if (to_dir) lock.emplace(bench::report_lock_target(dir));
  std::string json;
  {
    pyb::gil_scoped_release release;
    std::unique_ptr<bench::ProgressBar> bar;
    const bench::BenchResults r = bench::run_bench(o, registry, [&](long, long total, const std::string& note) {
      if (!progress) return;
      if (!bar) bar = std::make_unique<bench::ProgressBar>("bench", total);
      bar->advance(1, note);
    });
    if (bar) bar->finish();
    if (to_dir) {
      bench::write_report_directory(r, dir);
    } else {
      const bench::BenchStatistics stats = bench::bench_statistics(r);
      json = bench::summary_json(r, bench::summarise(r), bench::collect_provenance(), &stats);
    }
  }
  auto json_mod = pyb::module_::import("json");
  if (to_dir) {
    std::ifstream in(dir + "/summary.json");
    std::stringstream ss;
    ss << in.rdbuf();
    json = ss.str();
  }
  return json_mod.attr("loads")(json);
}

}  // namespace

void bind_bench(pyb::module_& m) {
  m.def("bench", &bench, pyb::arg("scene") = pyb::none(), pyb::arg("set") = pyb::dict(),
        pyb::arg("warmstarts") = pyb::none(), pyb::arg("seeds") = pyb::make_tuple(1, 2), pyb::arg("quick") = false,
        pyb::arg("mode") = "paired", pyb::arg("out") = pyb::none(), pyb::arg("sweeps") = pyb::none(),
        pyb::arg("tol") = 1e-2, pyb::arg("solver") = "pgs-colored", pyb::arg("steps") = pyb::none(),
        pyb::arg("model") = "", pyb::arg("progress") = false, pyb::arg("solvers") = pyb::none(),
        pyb::arg("accuracy") = 1e-6, pyb::arg("jobs") = 1,
        "The warm-start benchmark (`deepcontact bench`); returns the summary (summary.json) as a dict.\n\n"
        "solvers: a list of solver names (e.g. ['pgs', 'nncg', 'newton-sparse']) turns on the solver comparison "
        "(`--solvers`, paired mode): every solver solves every step from every starter's guess, and the summary gains "
        "'solvers': {SOLVER: {STARTER: {'reached_share', 'median_ms_to_accuracy', 'median_iterations_to_accuracy', "
        "'median_total_ms'}}}. accuracy: its target R (`--accuracy`), natural-map residual <= R x the heaviest "
        "body's weight m g (default 1e-6). jobs: seeds run at once on their own threads (`--jobs`); the results "
        "equal one thread's bar the timings.");
  m.def("warmstarters", [] { return user_registry().names(); }, "Names of the C++ warm starters.");
}

}  // namespace dc::py
