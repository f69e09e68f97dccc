// deepcontact.World, deepcontact.StepView and the scene arguments.
#include <pybind11/stl.h>

#include <cmath>
#include <filesystem>
#include <optional>

#include "dc/engine/trajectory_recorder.hpp"
#include "dc/core/error.hpp"
#include "dc/engine/scene.hpp"
#include "py_common.hpp"

namespace dc::py {

const World& PyWorld::get() const {
  if (changing != std::thread::id{} && changing != std::this_thread::get_id())
    throw std::runtime_error("World: another thread is stepping this World; a World is used by one thread at a "
                             "time (copy.copy(world) gives each thread its own)");
  if (owned) return *owned;
  if (!borrowed)
    throw InvalidArgument("this World is a warm-starter view that has expired (view.world is valid only during "
                          "the initial_guess/observe call)");
  return *borrowed;
}

World& PyWorld::mutable_world() {
  if (!owned) throw InvalidArgument("view.world is read-only (a warm starter may not step the world)");
  return *owned;
}

namespace {

/// A Python value as TOML text for apply_override.
std::string toml_value(pyb::handle v) {
  if (pyb::isinstance<pyb::bool_>(v)) return v.cast<bool>() ? "true" : "false";
  if (pyb::isinstance<pyb::int_>(v)) return pyb::str(v).cast<std::string>();
  if (pyb::isinstance<pyb::float_>(v)) return pyb::repr(v).cast<std::string>();
  if (pyb::isinstance<pyb::str>(v)) {
    std::string out = "\"";
    for (char c : v.cast<std::string>()) {
      if (c == '"' || c == '\\') out += '\\';
      out += c;
    }
    return out + "\"";
  }
  if (pyb::isinstance<pyb::sequence>(v) || pyb::hasattr(v, "tolist")) {
    pyb::object seq = pyb::hasattr(v, "tolist") ? v.attr("tolist")() : pyb::reinterpret_borrow<pyb::object>(v);
    std::string out = "[";
    bool first = true;
    for (auto item : seq) {
      out += (first ? "" : ", ") + toml_value(item);
      first = false;
    }
    return out + "]";
  }
  if (pyb::hasattr(v, "item")) return toml_value(v.attr("item")());  // numpy scalars
  throw pyb::type_error("set: cannot write " + pyb::repr(v).cast<std::string>() + " as a TOML value");
}

}  // namespace

WorldDef scene_from_python(pyb::handle scene, pyb::handle set) {
  WorldDef d;
  if (!scene.is_none()) {
    auto os = pyb::module_::import("os");
    const bool pathlike = pyb::isinstance(scene, os.attr("PathLike"));
    if (!pathlike && !pyb::isinstance<pyb::str>(scene))
      throw pyb::type_error("scene: expected None, TOML text (str) or a path (str or os.PathLike)");
    const std::string text = pathlike ? path_string(scene) : scene.cast<std::string>();
    // A path unless it is clearly TOML text (a newline, '=' or '['), like --scene F.
    const bool is_text = !pathlike && text.find_first_of("\n=[") != std::string::npos;
    d = is_text ? parse_scene(text, "<scene>") : load_scene(path_string(pyb::str(text)));  // no NUL
  }
  if (!set.is_none()) {
    if (pyb::isinstance<pyb::dict>(set)) {
      for (auto [k, v] : set.cast<pyb::dict>()) apply_override(d, pyb::str(k).cast<std::string>() + "=" + toml_value(v));
    } else if (pyb::isinstance<pyb::str>(set)) {  // one override, as after one --set
      apply_override(d, set.cast<std::string>());
    } else if (pyb::isinstance<pyb::list>(set) || pyb::isinstance<pyb::tuple>(set)) {
      for (auto item : set) {
        if (!pyb::isinstance<pyb::str>(item))
          throw pyb::type_error("set: expected \"section.key=value\" strings in the list, got " +
                                pyb::repr(item).cast<std::string>());
        apply_override(d, item.cast<std::string>());
      }
    } else {
      throw pyb::type_error("set: expected a dict {\"section.key\": value} or a list of \"section.key=value\" "
                            "strings, got " + std::string(pyb::str(pyb::type::handle_of(set).attr("__name__"))));
    }
  }
  d.validate();
  return d;
}

pyb::object contact_fields(std::span<const Contact> cs, const ContactConstraints* k) {
  const auto n = static_cast<pyb::ssize_t>(cs.size());
  pyb::array_t<int> body_a(n), body_b(n), key({n, pyb::ssize_t{3}});
  pyb::array_t<double> point({n, pyb::ssize_t{2}}), normal({n, pyb::ssize_t{2}}), gap(n), lam({n, pyb::ssize_t{2}}),
      approach(n);
  auto a = body_a.mutable_unchecked<1>();
  auto b = body_b.mutable_unchecked<1>();
  auto ky = key.mutable_unchecked<2>();
  auto p = point.mutable_unchecked<2>();
  auto nr = normal.mutable_unchecked<2>();
  auto g = gap.mutable_unchecked<1>();
  auto l = lam.mutable_unchecked<2>();
  auto ap = approach.mutable_unchecked<1>();
  for (pyb::ssize_t i = 0; i < n; ++i) {
    const Contact& c = cs[static_cast<std::size_t>(i)];
    a(i) = c.body_a;
    b(i) = c.body_b;
    ky(i, 0) = c.key.a;
    ky(i, 1) = c.key.b;
    ky(i, 2) = c.key.feature;
    p(i, 0) = c.point.x;
    p(i, 1) = c.point.y;
    nr(i, 0) = c.normal.x;
    nr(i, 1) = c.normal.y;
    g(i) = c.gap;
    l(i, 0) = c.lambda_n;
    l(i, 1) = c.lambda_t;
    ap(i) = c.approach_velocity;
  }
  pyb::object f = make_fields();
  f["body_a"] = body_a;
  f["body_b"] = body_b;
  f["key"] = key;
  f["point"] = point;
  f["normal"] = normal;
  f["gap"] = gap;
  f["lambda"] = lam;
  f["approach_velocity"] = approach;
  if (k && k->size() == static_cast<int>(n)) {
    pyb::array_t<int> normal_row(n), tangent_row(n);
    auto r0 = normal_row.mutable_unchecked<1>();
    auto r1 = tangent_row.mutable_unchecked<1>();
    for (pyb::ssize_t i = 0; i < n; ++i) {
      r0(i) = (*k)[static_cast<int>(i)].normal_row;
      r1(i) = (*k)[static_cast<int>(i)].tangent_row;
    }
    f["normal_row"] = normal_row;
    f["tangent_row"] = tangent_row;
  }
  return f;
}

namespace {

pyb::object body_fields(PyWorld& self, pyb::handle owner) {
  // The views point into the body arrays: bodies added later ([inflow], spawns) must not
  // move them (a view would read freed memory), so room for all of them is reserved first.
  // A view keeps the shape it was made with: the bodies that existed then.
  const BodyState& s = self.get().bodies();  // RuntimeError while another thread steps it
  if (self.owned) self.owned->reserve_added_bodies();
  const pyb::handle base = self.owned ? owner : pyb::none();  // a borrowed world's arrays are copies
  pyb::object f = make_fields();
  f["position"] = view(s.position, base);
  f["angle"] = view(s.angle, base);
  f["velocity"] = view(s.velocity, base);
  f["omega"] = view(s.omega, base);
  f["mass"] = view(s.mass, base);
  f["radius"] = view(s.radius, base);
  f["density"] = view(s.density, base);
  f["inertia"] = view(s.inertia, base);
  f["inv_mass"] = view(s.inv_mass, base);
  f["inv_inertia"] = view(s.inv_inertia, base);
  return f;
}

/// The contacts of the world's current step, with their rows once assembled.
pyb::object current_contacts(const World& w) {
  const bool assembled = w.constraints().size() == static_cast<int>(w.contacts().size());
  return contact_fields(w.contacts(), assembled ? &w.constraints() : nullptr);
}

pyb::object step(PyWorld& self, const std::optional<std::string>& solver_name, pyb::object warmstart,
                 std::optional<int> sweeps, std::optional<double> tol) {
  WorldChange change(self, "World.step");
  World& w = change.world();
  const auto solver = solver_name ? make_solver(*solver_name) : make_solver(w.def().solver.name);  // a name is parsed here
  SolverOptions opt = solver_options(w.def().solver);  // as `deepcontact simulate`
  if (sweeps) opt.max_sweeps = *sweeps;
  if (tol) opt.tolerance = *tol;
  if (opt.max_sweeps < 0) throw ConfigError("sweeps must be >= 0");
  if (!(opt.tolerance >= 0) || !std::isfinite(opt.tolerance)) throw ConfigError("tol must be finite and >= 0");
  std::unique_ptr<WarmStarter> python_starter;
  WarmStarter* ws = nullptr;
  if (pyb::isinstance<pyb::str>(warmstart)) {
    const auto spec = warmstart.cast<std::string>();
    auto& slot = self.starters[spec];
    if (!slot) slot = user_registry().make(spec);
    ws = slot.get();
  } else if (!warmstart.is_none()) {
    python_starter = make_python_warm_starter(warmstart);
    ws = python_starter.get();
  }
  StepReport r;
  {
    pyb::gil_scoped_release release;
    r = w.step(*solver, opt, [&](const World& ww) {
      return ws ? ws->initial_guess(StepView{ww, nullptr}) : Eigen::VectorXd::Zero(ww.problem().rows()).eval();
    });
    self.history.emplace_back('c', Eigen::VectorXd());
    self.history.emplace_back('a', Eigen::VectorXd());
    self.history.emplace_back('i', r.solve.lambda);
    if (ws) ws->observe(StepView{w, nullptr}, r.solve.lambda);
  }
  pyb::object f = make_fields();
  f["contacts"] = r.contacts;
  f["rows"] = r.rows;
  pyb::object result = pyb::cast(PyResult{std::move(r.solve)});
  f["solve"] = result;
  for (const char* k : {"lam", "status", "sweeps", "theta", "residual"}) f[k] = result.attr(k);
  pyb::dict prof;
  prof["collide_ms"] = r.profile.collide_ms;
  prof["assemble_ms"] = r.profile.assemble_ms;
  prof["warmstart_ms"] = r.profile.warmstart_ms;
  prof["solve_ms"] = r.profile.solve_ms;
  prof["integrate_ms"] = r.profile.integrate_ms;
  f["profile"] = prof;
  return f;
}

/// A copy of an owned world (the engine state and its history; named starters start afresh).
std::shared_ptr<PyWorld> copy_world(const PyWorld& self) {
  if (!self.owned) throw InvalidArgument("a warm starter's view.world cannot be copied (copy the World you step)");
  (void)self.get();  // not while another thread steps it
  auto out = std::make_shared<PyWorld>();
  out->owned = std::make_unique<World>(*self.owned);
  out->history = self.history;
  return out;
}

/// pickle: the complete scene (TOML) and the stages applied since; loading replays them.
pyb::tuple world_state(const PyWorld& self) {
  if (!self.owned) throw InvalidArgument("a warm starter's view.world cannot be pickled (pickle the World you step)");
  (void)self.get();  // not while another thread steps it
  pyb::list ops;
  for (const auto& [op, lam] : self.history)
    ops.append(pyb::make_tuple(std::string(1, op), op == 'i' ? pyb::object(copy(lam)) : pyb::object(pyb::none())));
  return pyb::make_tuple(scene_to_toml(self.owned->def()), ops);
}

std::shared_ptr<PyWorld> world_from_state(const pyb::tuple& state) {
  if (state.size() != 2) throw InvalidArgument("World pickle: expected (scene, stages), got " + std::to_string(state.size()) + " items");
  auto w = std::make_shared<PyWorld>();
  w->owned = std::make_unique<World>(parse_scene(state[0].cast<std::string>(), "<pickled World>"));
  for (auto item : state[1].cast<pyb::list>()) {
    const auto t = item.cast<pyb::tuple>();
    const std::string op = t[0].cast<std::string>();
    if (op == "c") w->owned->collide();
    else if (op == "a") w->owned->assemble();
    else if (op == "i") w->owned->integrate(to_vector(t[1], "pickled λ"));
    else throw InvalidArgument("World pickle: unknown stage '" + op + "'");
    w->history.emplace_back(op[0], op == "i" ? to_vector(t[1], "pickled λ") : Eigen::VectorXd());
  }
  return w;
}

}  // namespace

void bind_world(pyb::module_& m) {
  pyb::class_<PyWorld, std::shared_ptr<PyWorld>>(
      m, "World",
      "The 2D impulse engine (dc::World). World(scene=None, set={}): scene = a TOML path or text (None = the seed "
      "scene), set = the --set overrides. copy.copy/copy.deepcopy give an independent world in the same state; "
      "pickle stores the scene and the stages applied, and loading replays them (bit-equal).")
      .def(pyb::init([](pyb::object scene, pyb::object set) {
             WorldDef d = scene_from_python(scene, set);
             auto w = std::make_shared<PyWorld>();
             pyb::gil_scoped_release release;
             w->owned = std::make_unique<World>(std::move(d));
             return w;
           }),
           pyb::arg("scene") = pyb::none(), pyb::arg("set") = pyb::dict(),
           "A world of the scene (a TOML path or text; None = the seed scene) with the overrides `set` "
           "({\"section.key\": value} or [\"section.key=value\", …]).")
      .def("collide",
           [](PyWorld& self) {
             WorldChange change(self, "World.collide");
             World& w = change.world();
             {
               pyb::gil_scoped_release release;
               w.collide();
             }
             self.history.emplace_back('c', Eigen::VectorXd());
             return contact_fields(w.contacts(), nullptr);
           },
           "Broad + narrow phase; returns this step's contacts.")
      .def("assemble",
           [](PyWorld& self) {
             WorldChange change(self, "World.assemble");
             World& w = change.world();
             {
               pyb::gil_scoped_release release;
               w.assemble();
             }
             self.history.emplace_back('a', Eigen::VectorXd());
             return problem_to_python(w.problem());
           },
           "Contact rows, J, M⁻¹, b and bounds; returns the Problem (A formed when .A is read).")
      .def("integrate",
           [](PyWorld& self, pyb::object lam) {
             WorldChange change(self, "World.integrate");
             World& w = change.world();
             const Eigen::VectorXd l = lam.is_none() ? Eigen::VectorXd::Zero(w.problem().rows()).eval()
                                                     : to_vector(lam, "lam");
             if (l.size() != w.problem().rows())
               throw InvalidArgument("integrate: λ has " + std::to_string(l.size()) + " entries, the problem has " +
                                     std::to_string(w.problem().rows()) + " rows");
             // A NaN or infinite impulse would turn every body it touches into NaN for good.
             for (Eigen::Index i = 0; i < l.size(); ++i)
               if (!std::isfinite(l[i]))
                 throw InvalidArgument("integrate: λ[" + std::to_string(i) + "] = " + std::to_string(l[i]) +
                                       " is not finite");
             {
               pyb::gil_scoped_release release;
               w.integrate(l);
             }
             self.history.emplace_back('i', l);
           },
           pyb::arg("lam"), "Advance the bodies with the contact forces λ (one per problem row; None = zeros).")
      .def("step", &step, pyb::arg("solver") = pyb::none(), pyb::arg("warmstart") = "builtin",
           pyb::arg("sweeps") = pyb::none(), pyb::arg("tol") = pyb::none(),
           "One whole step (collide, assemble, warm start, solve, integrate), as `deepcontact simulate` does it. "
           "solver, sweeps, tol: None = the scene's [solver] name, sweeps and tolerance. warmstart: a starter name "
           "(warmstarters()), a Python starter object, or None (zeros). One thread at a time: a step from another "
           "thread while this one runs, or from inside a warm starter, raises RuntimeError. Returns a Fields report: contacts, rows, "
           "solve (the Result), lam, status, sweeps, theta, residual, profile (ms per stage).")
      .def("_write_trajectory",
           [](const PyWorld& self, pyb::object path) {
             const World& w = self.get();
             TrajectoryRecorder(w).write(path_string(path), scene_to_toml(w.def()), "");
           },
           pyb::arg("path"), "The current state as a one-state trajectory file (World.render draws it).")
      .def("render", [](pyb::object self) { return pyb::module_::import("deepcontact").attr("_render_world")(self); },
           "The current state drawn as `deepcontact render` draws a frame (bodies, walls, the contact forces of "
           "the last step): an (H, W, 3) uint8 numpy array (PIL.Image.fromarray(a) or plt.imshow(a) shows it).")
      .def_property_readonly("bodies", [](pyb::object self) { return body_fields(self.cast<PyWorld&>(), self); },
                             "Body state as numpy arrays (views into the world: they follow the simulation): "
                             "position (n, 2), angle, velocity (n, 2), omega, mass, radius, density, inertia, "
                             "inv_mass, inv_inertia. Writes are checked at the next step, collide, assemble or "
                             "integrate (a ValueError for a non-finite value, radius <= 0 or a negative mass, "
                             "inertia or inverse).")
      .def_property_readonly("contacts", [](const PyWorld& self) { return current_contacts(self.get()); },
                             "This step's contacts (copies): body_a, body_b, key, point, normal, gap, lambda "
                             "(λ_n, λ_t), approach_velocity; normal_row, tangent_row once assembled.")
      .def_property_readonly("previous_contacts",
                             [](const PyWorld& self) { return contact_fields(self.get().previous_contacts(), nullptr); },
                             "The previous step's contacts with their solved λ (builtin's memory).")
      .def_property_readonly("problem", [](const PyWorld& self) { return problem_to_python(self.get().problem()); },
                             "The current step's Problem (a copy: the next assemble() replaces the world's).")
      .def_property_readonly("rows", [](const PyWorld& self) { return self.get().problem().rows(); },
                             "Rows of the current problem (2 per contact with friction, 1 without).")
      .def_property_readonly("time", [](const PyWorld& self) { return self.get().time(); },
                             "Simulated time t = step_index · dt [s].")
      .def_property_readonly("step_index", [](const PyWorld& self) { return self.get().step_index(); },
                             "Steps taken (integrate() calls) since the start.")
      .def_property_readonly("scene", [](const PyWorld& self) { return scene_to_toml(self.get().def()); },
                             "The complete scene as TOML.")
      .def_property_readonly("hash",
                             [](const PyWorld& self) {
                               char buf[17];
                               std::snprintf(buf, sizeof buf, "%016llx",
                                             static_cast<unsigned long long>(state_hash(self.get().bodies())));
                               return std::string(buf);
                             },
                             "The final-state hash `deepcontact simulate --hash` prints (16 hex digits).")
      .def("kinetic_energy", [](const PyWorld& self) { return self.get().kinetic_energy(); },
           "Σ ½ m v² + ½ I ω² over the bodies [J].")
      .def("potential_energy", [](const PyWorld& self) { return self.get().potential_energy(); },
           "Σ −m g·x over the bodies [J] (zero at the origin).")
      .def("max_penetration", [](const PyWorld& self) { return self.get().max_penetration(); },
           "max(0, −min gap) over the current contacts [m].")
      .def("pack",
           [](const PyWorld& self, const std::vector<double>& lambda_n, const std::vector<double>& lambda_t) {
             return copy(self.get().pack(lambda_n, lambda_t));
           },
           pyb::arg("lambda_n"), pyb::arg("lambda_t") = std::vector<double>{},
           "Per-contact forces (λ_n, λ_t: one per current contact; λ_t may be empty without friction) → "
           "the row vector λ of the current problem.")
      .def_property_readonly("is_view", [](const PyWorld& self) { return !self.owned; },
                             "True for a warm starter's read-only view.world (valid during the call only).")
      .def("__copy__", [](const PyWorld& self) { return copy_world(self); },
           "An independent world in the same state (as deepcopy: the engine state is always copied).")
      .def("__deepcopy__", [](const PyWorld& self, pyb::dict) { return copy_world(self); }, pyb::arg("memo"),
           "An independent world in the same state; named warm starters of step() start afresh.")
      .def(pyb::pickle([](const PyWorld& self) { return world_state(self); },
                       [](const pyb::tuple& state) { return world_from_state(state); }))
      .def("__repr__", [](const PyWorld& self) {
        if (!self.owned && !self.borrowed) return std::string("<deepcontact.World (expired view)>");
        const World& w = self.get();
        return "<deepcontact.World bodies=" + std::to_string(w.bodies().size()) +
               " step=" + std::to_string(w.step_index()) + " t=" + std::to_string(w.time()) + ">";
      });

  pyb::class_<PyStepView, std::shared_ptr<PyStepView>>(
      m, "StepView", "What a warm starter sees: .world (read-only, valid during the call) and .oracle (λ* or None).")
      .def_property_readonly("world", [](const PyStepView& v) { return v.world; },
                             "The World being stepped, read-only; it expires when the call returns.")
      .def_property_readonly("oracle", [](const PyStepView& v) { return v.oracle; },
                             "This step's solved λ* (numpy) when the bench shares it (paired mode), else None.")
      .def_property_readonly("rows", [](const PyStepView& v) { return v.world->get().problem().rows(); },
                             "Rows of this step's problem (= len of the λ⁰ to return).");
}

}  // namespace dc::py
