#pragma once
// A whole data set in one call (`deepcontact generate`; layout in docs/formats.md "Data
// set"): M simulations of a seed family run in parallel, written in order, resumable.
//
// Threads: simulations run on OpenMP worker threads (each a pure function of its index,
// SimulationGenerator, so the results do not depend on the thread count); ONE writer thread
// appends them to the file strictly in simulation order, so the file's datasets are
// identical for any thread count. Finished simulations wait in memory for their turn; a
// worker does not start a simulation more than 2·T ahead of the writer, which bounds that
// memory.
//
// Nothing lost: the file is OUT.partial until all M simulations are in, then renamed to OUT.
// Each simulation is committed by its /sims row (written last) and a flush
// (DataSetWriter::append), so a crash loses at most the simulations in flight; `resume`
// continues from the last committed one. When `keep_going` returns false (e.g. after
// SIGINT) the workers drop their unfinished simulations, the writer commits what is
// finished, and generate_data_set returns with finished = false.
#include <cstdint>
#include <functional>
#include <string>

#include "dc/learning/data_set.hpp"

namespace dc {

/// What to generate and where.
struct DataSetGenerationDef {
  DataSetParams params;     ///< the content (validated)
  std::string out;          ///< final path; OUT.partial while incomplete
  int simulations = 1;      ///< M ≥ 1 (a resumed run may ask for more than the first one did)
  int threads = 0;          ///< worker threads; 0 = OpenMP's default (OMP_NUM_THREADS or all cores)
  bool resume = false;      ///< continue OUT.partial (same params; ConfigError otherwise)
  bool force = false;       ///< replace an existing OUT
};

/// Optional callbacks. on_start and on_committed run on the writer thread (one at a time).
struct DataSetGenerationHooks {
  std::function<bool()> keep_going;                          ///< polled between steps; false = stop
  std::function<void(int first, int threads)> on_start;      ///< before the first simulation: committed so far
  std::function<void(const SimulationRecord&)> on_committed; ///< after each simulation is in the file
};

struct DataSetGenerationReport {
  int first = 0;              ///< simulations already committed when this run started (resume)
  int completed = 0;          ///< simulations committed now
  int threads = 0;            ///< worker threads used
  bool finished = false;      ///< all M are in and the file was renamed to OUT
  std::string path;           ///< OUT when finished, else OUT.partial
  std::int64_t samples = 0;   ///< sample rows in the file
  long steps = 0;             ///< steps simulated by this run (committed simulations)
  double worst_residual = 0;  ///< worst natural-map residual of λ* over this run's simulations [N]
  double wall_seconds = 0;    ///< of the simulations and writing
};

/// Generates the data set (see the file comment). ConfigError for bad settings (M < 1, no
/// OUT, negative threads, OUT exists without force, resume without OUT.partial or a stale
/// OUT.partial without resume, parameters that differ from the interrupted run's); IoError
/// for file errors; a simulation's exception is rethrown after the writer stopped.
DataSetGenerationReport generate_data_set(const DataSetGenerationDef& def, const DataSetGenerationHooks& hooks = {});

}  // namespace dc
