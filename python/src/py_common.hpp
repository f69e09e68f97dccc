#pragma once
// Shared pieces of the Python module (deepcontact._core): numpy views and copies of the
// engine's arrays, scipy.sparse CSR matrices of Eigen's row-major sparse matrices, and the
// Python-side wrappers of the engine objects (world, problem, solve result).
//
// Ownership: a numpy array that views C++ memory has the Python object that owns that memory
// as its base, so the memory lives as long as the array. Memory that the next engine stage
// replaces (this step's contacts, a warm-starter view's world) is copied instead.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <Eigen/Core>
#include <filesystem>
#include <map>
#include <utility>
#include <memory>
#include <span>
#include <string>
#include <thread>
#include <vector>

#include "dc/core/vec2.hpp"
#include "dc/lcp/lcp_problem.hpp"
#include "dc/lcp/lcp_solver.hpp"
#include "dc/engine/world.hpp"
#include "dc/warmstart/warm_starter.hpp"

namespace dc::py {

namespace pyb = pybind11;

// ---- numpy --------------------------------------------------------------------------
/// 1-D float64 array viewing `n` doubles at `data`, kept alive by `base` (copied when base
/// is None).
pyb::array_t<double> view(const double* data, std::size_t n, pyb::handle base);
/// (n, 2) float64 array of Vec2s (a view when base is not None).
pyb::array_t<double> view(const std::vector<Vec2>& v, pyb::handle base);
pyb::array_t<double> view(const std::vector<double>& v, pyb::handle base);
/// (A VectorXd or a KeptVector: a view of its entries, never of a temporary copy.)
pyb::array_t<double> view(const Eigen::Ref<const Eigen::VectorXd>& v, pyb::handle base);
/// Copy of a vector into a new array.
pyb::array_t<double> copy(const Eigen::Ref<const Eigen::VectorXd>& v);
/// `a` with numpy's writeable flag cleared (a view callers must not change).
pyb::array read_only(pyb::array a);
/// TypeError naming `what` unless `obj` (array-like or scipy.sparse) holds real numbers:
/// booleans, integers or floats — complex (its imaginary part would be dropped), object,
/// text and record arrays are refused.
void require_real_numbers(pyb::handle obj, const std::string& what);
/// A float64 vector from any array-like of real numbers (TypeError for complex or object
/// arrays, ValueError naming `what` for a wrong shape).
Eigen::VectorXd to_vector(pyb::handle obj, const std::string& what);
/// to_vector, and a ValueError naming `what` unless it has exactly `n` entries.
Eigen::VectorXd to_vector_of_size(pyb::handle obj, const std::string& what, Eigen::Index n);
/// scipy.sparse.csr_matrix viewing a compressed row-major matrix (kept alive by `base`).
pyb::object csr_view(const SparseRowMatrix& m, pyb::handle base);
/// Any scipy.sparse matrix or dense array-like → row-major sparse (ValueError on bad input:
/// not 2-D, row pointers or column indices outside the shape, sizes that do not match).
SparseRowMatrix to_sparse(pyb::handle obj, const std::string& what);
/// A str or os.PathLike giving a str, as a path string: TypeError for anything else (bytes
/// included), ValueError for an empty path or one holding a NUL.
std::string path_string(pyb::handle path);
/// A deepcontact.Fields (dict with attribute access) — the package defines the class.
pyb::object make_fields();

// ---- wrapped engine objects -------------------------------------------------------
/// deepcontact.Problem: an LCP (owned; a copy of the world's problem of that step).
struct PyProblem {
  std::shared_ptr<LcpProblem> p;
};

/// A Python Problem owning (a copy of) `p`, its sparse matrices compressed for CSR views.
pyb::object problem_to_python(LcpProblem p);

/// deepcontact.Result: the outcome of a solve.
struct PyResult {
  SolveResult r;
};

/// deepcontact.World. Owns its dc::World, or (view.world inside a warm-starter call)
/// borrows one read-only for the duration of that call; afterwards the borrowed object
/// raises instead of reading freed memory.
struct PyWorld {
  std::unique_ptr<World> owned;
  const World* borrowed = nullptr;
  /// Named warm starters step() has used (kept across steps: some observe the solution).
  std::map<std::string, std::unique_ptr<WarmStarter>> starters;
  /// Every stage that changed the owned world since it was made, in order: 'c' collide, 'a'
  /// assemble, 'i' integrate with the λ it was given. The engine is deterministic, so
  /// replaying them on World(scene) gives the bit-equal world: that is what pickle stores.
  std::vector<std::pair<char, Eigen::VectorXd>> history;
  /// The thread inside a call that changes the owned world (step, collide, assemble,
  /// integrate), or no thread. Read and written with the GIL held; the engine runs without it.
  std::thread::id changing{};

  /// The world to read: RuntimeError while another thread changes it (the engine runs
  /// without the GIL); the changing thread itself (a warm starter's callback) may read.
  [[nodiscard]] const World& get() const;
  World& mutable_world();
};

/// Held for the whole of a call that changes a PyWorld's owned world: a second such call
/// raises RuntimeError — from another thread (a World is stepped by one thread at a time;
/// copy.copy gives each thread its own) or re-entered from a warm starter on the same
/// thread — and so does a read from another thread meanwhile. Also refuses (InvalidArgument)
/// a body state broken through the writable World.bodies views (check_bodies).
class WorldChange {
 public:
  explicit WorldChange(PyWorld& w, const char* call);
  ~WorldChange() { w_.changing = std::thread::id{}; }
  WorldChange(const WorldChange&) = delete;
  WorldChange& operator=(const WorldChange&) = delete;
  World& world() { return *w_.owned; }

 private:
  PyWorld& w_;
};

/// InvalidArgument naming `call`, the body and the value unless every body keeps the
/// engine's invariants: position, velocity, angle, ω finite; radius finite and > 0; mass,
/// inertia, their inverses and density finite and >= 0 (0: a static body).
void check_bodies(const BodyState& s, const char* call);

/// The Python view of a dc::StepView: a borrowed World plus a copy of the oracle λ*.
/// Call expire() when the C++ call it belongs to returns.
struct PyStepView {
  std::shared_ptr<PyWorld> world;
  pyb::object oracle;  ///< numpy copy or None
  void expire() { world->borrowed = nullptr; }
};

/// Per-contact fields (Fields of numpy arrays) of a list of contacts; with rows of the
/// current problem when `constraints` matches them.
pyb::object contact_fields(std::span<const Contact> contacts, const ContactConstraints* constraints);

/// A scene from World(scene=…, set=…): None = the seed scene, a path (str or os.PathLike) of
/// a TOML file, or TOML text; `set` maps "section.key" to a value (Python numbers, str,
/// bools and lists become TOML) or is a list of "section.key=value" strings as on the
/// command line. Validated; errors are the CLI's ConfigErrors.
WorldDef scene_from_python(pyb::handle scene, pyb::handle set);

// ---- warm starters written in Python ----------------------------------------------
/// A dc::WarmStarter that calls a Python object (duck-typed: initial_guess(view), optional
/// name(), observe(view, solved), uses_oracle()). Safe to call without the GIL: it takes the
/// GIL for every call into Python.
std::unique_ptr<WarmStarter> make_python_warm_starter(pyb::handle obj);
/// The shipped model, models/default.h5 of the source tree the module was built from.
std::filesystem::path shipped_model();
/// The starters a user's run draws from: default_warm_starters() and the cnn starters with the
/// shipped model. The oracles and negative controls of dc_research are not linked into the
/// module (`deepcontact bench` has them; docs/python.md).
WarmStarterRegistry user_registry();
/// bench(warmstarts=None)'s list: zero, builtin, builtin-extrapolate, builtin-statics,
/// sph-prev (quick: zero, builtin), plus cnn when the shipped model exists — `deepcontact
/// bench`'s default list without its oracles and controls.
std::vector<std::string> default_python_bench_starters(bool quick);

// ---- registration (one file each) -------------------------------------------------
void bind_errors(pyb::module_& m);
void bind_problem_file(pyb::module_& m);
void bind_problem(pyb::module_& m);
void bind_world(pyb::module_& m);
void bind_bench(pyb::module_& m);
void bind_io(pyb::module_& m);

}  // namespace dc::py
