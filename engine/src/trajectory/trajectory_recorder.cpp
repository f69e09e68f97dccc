#include "dc/engine/trajectory_recorder.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>

#include "dc/core/error.hpp"
#include "dc/io/h5.hpp"
#include "trajectory_layout.hpp"

namespace dc {

TrajectoryRecorder::TrajectoryRecorder(const World& world)
    : n_(world.bodies().size()), start_step_(world.step_index()) {
  const BodyState& s = world.bodies();
  record_state(s);
  step_offset_.push_back(0);
}

void TrajectoryRecorder::record_state(const BodyState& s) {
  // Bodies are only ever appended (inflow.hpp): a state has at least the bodies of the last.
  if (s.size() < radius_.size()) throw InvalidArgument("TrajectoryRecorder: the number of bodies decreased");
  if (s.size() != radius_.size()) {  // first state, or bodies were appended: refresh the tables
    radius_.assign(s.radius.begin(), s.radius.end());
    mass_.assign(s.mass.begin(), s.mass.end());
    shapes_ = s.shapes;
  }
  n_ = s.size();
  state_size_.push_back(n_);
  for (std::size_t k = 0; k < n_; ++k) {
    position_.push_back(s.position[k].x);
    position_.push_back(s.position[k].y);
    angle_.push_back(s.angle[k]);
    velocity_.push_back(s.velocity[k].x);
    velocity_.push_back(s.velocity[k].y);
    omega_.push_back(s.omega[k]);
  }
}

void TrajectoryRecorder::reserve_steps(int steps) {
  if (steps <= 0) return;
  const std::size_t more = static_cast<std::size_t>(steps) * n_;
  position_.reserve(position_.size() + 2 * more);
  velocity_.reserve(velocity_.size() + 2 * more);
  angle_.reserve(angle_.size() + more);
  omega_.reserve(omega_.size() + more);
  const auto s = static_cast<std::size_t>(steps);
  step_offset_.reserve(step_offset_.size() + s);
  sweeps_.reserve(sweeps_.size() + s);
  status_.reserve(status_.size() + s);
  theta_final_.reserve(theta_final_.size() + s);
  residual_.reserve(residual_.size() + s);
  profile_.reserve(profile_.size() + s * kProfileWidth);
}

void TrajectoryRecorder::record_step(const World& w, const StepReport& r) {
  const auto t0 = std::chrono::steady_clock::now();
  for (const Contact& c : w.contacts()) {
    body_a_.push_back(c.body_a);
    body_b_.push_back(c.body_b);
    point_.push_back(c.point.x);
    point_.push_back(c.point.y);
    normal_.push_back(c.normal.x);
    normal_.push_back(c.normal.y);
    gap_.push_back(c.gap);
    lambda_.push_back(c.lambda_n);
    lambda_.push_back(c.lambda_t);
    feature_.push_back(c.key.feature);
  }
  step_offset_.push_back(static_cast<std::int64_t>(body_a_.size()));
  sweeps_.push_back(r.solve.sweeps);
  status_.push_back(static_cast<std::int32_t>(r.solve.status));
  theta_final_.push_back(r.solve.theta.empty() ? 0.0 : r.solve.theta.back());
  residual_.push_back(r.solve.residual);
  record_state(w.bodies());
  const StepProfile& p = r.profile;
  const double record_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  profile_.insert(profile_.end(), {1e-3 * p.collide_ms, 1e-3 * p.assemble_ms, 1e-3 * p.warmstart_ms,
                                   1e-3 * p.solve_ms, 1e-3 * p.integrate_ms, record_s, 1e-3 * p.broad_phase_ms});
}

void TrajectoryRecorder::write(const std::string& path, const std::string& scene,
                               const std::string& warmstart) const {
  const hsize_t S = sweeps_.size(), n = n_, C = body_a_.size();
  // States recorded before late bodies entered are padded with NaN (docs/formats.md).
  std::vector<double> position, angle, velocity, omega;
  const std::vector<double>* pos = &position_;
  const std::vector<double>* ang = &angle_;
  const std::vector<double>* vel = &velocity_;
  const std::vector<double>* om = &omega_;
  if (position_.size() != 2 * n * (S + 1)) {
    const double nan = std::numeric_limits<double>::quiet_NaN();
    position.assign(2 * n * (S + 1), nan);
    velocity.assign(2 * n * (S + 1), nan);
    angle.assign(n * (S + 1), nan);
    omega.assign(n * (S + 1), nan);
    std::size_t src = 0;
    for (std::size_t i = 0; i < state_size_.size(); ++i) {
      const std::size_t m = state_size_[i];
      std::copy_n(position_.begin() + static_cast<std::ptrdiff_t>(2 * src), 2 * m, position.begin() + static_cast<std::ptrdiff_t>(2 * n * i));
      std::copy_n(velocity_.begin() + static_cast<std::ptrdiff_t>(2 * src), 2 * m, velocity.begin() + static_cast<std::ptrdiff_t>(2 * n * i));
      std::copy_n(angle_.begin() + static_cast<std::ptrdiff_t>(src), m, angle.begin() + static_cast<std::ptrdiff_t>(n * i));
      std::copy_n(omega_.begin() + static_cast<std::ptrdiff_t>(src), m, omega.begin() + static_cast<std::ptrdiff_t>(n * i));
      src += m;
    }
    pos = &position; ang = &angle; vel = &velocity; om = &omega;
  }
  const H5DatasetOptions z{.extendible = false, .chunk_rows = 0, .deflate = 4};
  const auto opt = [&](hsize_t rows) { return rows > 0 ? z : H5DatasetOptions{}; };
  AtomicH5File out(path);
  H5File& f = out.file();
  trajectory::write_attributes(f, scene, warmstart);
  // State k is the world after start_step + k steps: its time is (start_step + k)·dt (the
  // bench's reference starts after the warm-up).
  f.set_attribute<std::int32_t>("/", "start_step", start_step_);
  f.write<double>("/bodies/position", *pos, {S + 1, n, 2}, opt(S + 1));
  f.write<double>("/bodies/angle", *ang, {S + 1, n}, opt(S + 1));
  f.write<double>("/bodies/velocity", *vel, {S + 1, n, 2}, opt(S + 1));
  f.write<double>("/bodies/omega", *om, {S + 1, n}, opt(S + 1));
  trajectory::write_body_tables(f, n_, radius_, mass_, shapes_);
  f.write<std::int64_t>("/contacts/step_offset", step_offset_, {S + 1});
  f.write<std::int32_t>("/contacts/body_a", body_a_, {C}, opt(C));
  f.write<std::int32_t>("/contacts/body_b", body_b_, {C}, opt(C));
  f.write<double>("/contacts/point", point_, {C, 2}, opt(C));
  f.write<double>("/contacts/normal", normal_, {C, 2}, opt(C));
  f.write<double>("/contacts/gap", gap_, {C}, opt(C));
  f.write<double>("/contacts/lambda", lambda_, {C, 2}, opt(C));
  f.write<std::int32_t>("/contacts/feature", feature_, {C}, opt(C));
  f.write<std::int32_t>("/solver/sweeps", sweeps_, {S});
  f.write<std::int32_t>("/solver/status", status_, {S});
  f.write<double>("/solver/theta_final", theta_final_, {S});
  f.write<double>("/solver/residual", residual_, {S});
  f.write<double>("/solver/profile", profile_, {S, static_cast<hsize_t>(kProfileWidth)});
  f.set_attribute("/solver/profile", "columns", kProfileColumns);
  f.set_attribute("/solver/profile", "units", "s");
  out.commit();
}

}  // namespace dc
