// WorldChange and check_bodies (py_common.hpp): what keeps a Python World consistent when
// threads, warm starters and the writable body views touch it.
#include <cmath>
#include <stdexcept>

#include "dc/core/error.hpp"
#include "py_common.hpp"

namespace dc::py {

WorldChange::WorldChange(PyWorld& w, const char* call) : w_(w) {
  if (!w.owned) throw InvalidArgument("view.world is read-only (a warm starter may not step the world)");
  const std::thread::id me = std::this_thread::get_id();
  if (w.changing == me)
    throw std::runtime_error(std::string(call) + ": this World is already being stepped on this thread (called "
                             "from a warm starter or callback of its own step?); a World is not re-entered");
  if (w.changing != std::thread::id{})
    throw std::runtime_error(std::string(call) + ": another thread is stepping this World; a World is used by one "
                             "thread at a time (copy.copy(world) gives each thread its own)");
  check_bodies(w.owned->bodies(), call);
  w.changing = me;
}

namespace {

[[noreturn]] void refuse(const char* call, std::size_t k, const char* what, double v, const char* rule) {
  throw InvalidArgument(std::string(call) + ": body " + std::to_string(k) + ": " + what + " = " + std::to_string(v) +
                        " must be " + rule + " (changed through World.bodies?)");
}

}  // namespace

void check_bodies(const BodyState& s, const char* call) {
  for (std::size_t k = 0; k < s.radius.size(); ++k) {
    const std::pair<const char*, double> finite[] = {
        {"position.x", s.position[k].x}, {"position.y", s.position[k].y}, {"velocity.x", s.velocity[k].x},
        {"velocity.y", s.velocity[k].y}, {"angle", s.angle[k]},           {"omega", s.omega[k]}};
    for (const auto& [what, v] : finite)
      if (!std::isfinite(v)) refuse(call, k, what, v, "finite");
    if (!(s.radius[k] > 0) || !std::isfinite(s.radius[k])) refuse(call, k, "radius", s.radius[k], "finite and > 0");
    const std::pair<const char*, double> non_negative[] = {{"density", s.density[k]},   {"mass", s.mass[k]},
                                                           {"inertia", s.inertia[k]},   {"inv_mass", s.inv_mass[k]},
                                                           {"inv_inertia", s.inv_inertia[k]}};
    for (const auto& [what, v] : non_negative)
      if (!(v >= 0) || !std::isfinite(v)) refuse(call, k, what, v, "finite and >= 0");
  }
}

}  // namespace dc::py
