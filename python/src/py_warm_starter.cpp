// Warm starters written in Python (deepcontact.WarmStarter and any duck-typed object), and
// the C++ registry the module uses.
#include "dc/cnn/cnn_warm_starter.hpp"
#include "dc/core/error.hpp"
#include "py_common.hpp"
#include "dc/core/install_paths.hpp"

namespace dc::py {
namespace {

class PythonWarmStarter final : public WarmStarter {
 public:
  /// Needs the GIL.
  explicit PythonWarmStarter(pyb::object obj) : obj_(std::move(obj)) {
    if (!pyb::hasattr(obj_, "initial_guess"))
      throw pyb::type_error("warm starter " + pyb::repr(obj_).cast<std::string>() +
                            " has no initial_guess(view) method");
    name_ = pyb::hasattr(obj_, "name") ? pyb::str(obj_.attr("name")()).cast<std::string>()
                                       : pyb::str(pyb::type::of(obj_).attr("__name__")).cast<std::string>();
    has_observe_ = pyb::hasattr(obj_, "observe");
    if (pyb::hasattr(obj_, "uses_oracle")) {
      pyb::object u = obj_.attr("uses_oracle");
      uses_oracle_ = (PyCallable_Check(u.ptr()) ? u() : u).cast<bool>();
    }
  }
  ~PythonWarmStarter() override {
    pyb::gil_scoped_acquire gil;  // the bench destroys starters without the GIL
    obj_ = pyb::object();
  }
  PythonWarmStarter(const PythonWarmStarter&) = delete;
  PythonWarmStarter& operator=(const PythonWarmStarter&) = delete;

  [[nodiscard]] std::string name() const override { return name_; }
  [[nodiscard]] bool uses_oracle() const override { return uses_oracle_; }

  Eigen::VectorXd initial_guess(const StepView& v) override {
    pyb::gil_scoped_acquire gil;
    Call call(v);
    Eigen::VectorXd out = to_vector(obj_.attr("initial_guess")(call.view), "warm starter '" + name_ + "'");
    const int rows = v.world.problem().rows();
    // The bench's messages for C++ starters (bench_runner.cpp), so both kinds fail alike.
    if (out.size() != rows)
      throw InvalidArgument("warm starter '" + name_ + "' returned " + std::to_string(out.size()) +
                            " values for a problem with " + std::to_string(rows) + " rows");
    if (!out.allFinite()) throw InvalidArgument("warm starter '" + name_ + "' returned a non-finite guess");
    return out;
  }

  void observe(const StepView& v, const Eigen::VectorXd& solved) override {
    if (!has_observe_) return;
    pyb::gil_scoped_acquire gil;
    Call call(v);
    obj_.attr("observe")(call.view, copy(solved));
  }

 private:
  /// The Python view of one call; its world expires when the call returns (also on error).
  struct Call {
    std::shared_ptr<PyStepView> state;
    pyb::object view;
    explicit Call(const StepView& v) : state(std::make_shared<PyStepView>()) {
      state->world = std::make_shared<PyWorld>();
      state->world->borrowed = &v.world;
      state->oracle = v.oracle ? pyb::object(copy(*v.oracle)) : pyb::none();
      view = pyb::cast(state);
    }
    ~Call() { state->expire(); }
    Call(const Call&) = delete;
    Call& operator=(const Call&) = delete;
  };

  pyb::object obj_;
  std::string name_;
  bool has_observe_ = false;
  bool uses_oracle_ = false;
};

}  // namespace

std::unique_ptr<WarmStarter> make_python_warm_starter(pyb::handle obj) {
  return std::make_unique<PythonWarmStarter>(pyb::reinterpret_borrow<pyb::object>(obj));
}

std::filesystem::path shipped_model() { return data_path("models/default.h5"); }

WarmStarterRegistry user_registry() {
  WarmStarterRegistry r = default_warm_starters();
  add_cnn_warm_starters(r, shipped_model());
  return r;
}

std::vector<std::string> default_python_bench_starters(bool quick) {
  std::vector<std::string> out = {"zero", "builtin"};
  if (!quick) out.insert(out.end(), {"builtin-extrapolate", "builtin-statics", "sph-prev"});
  // cnn only when the shipped model is there, as in `deepcontact bench`'s default list.
  if (std::filesystem::exists(shipped_model())) out.push_back("cnn");
  return out;
}

}  // namespace dc::py
