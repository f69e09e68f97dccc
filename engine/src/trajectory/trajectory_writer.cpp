// TrajectoryWriter: the trajectory streamed to OUT.tmp, renamed at commit (trajectory_writer.hpp).
#include "dc/engine/trajectory_writer.hpp"

#include <filesystem>

#include "dc/engine/trajectory_recorder.hpp"
#include "dc/core/error.hpp"
#include "dc/io/atomic_file.hpp"
#include "dc/io/h5.hpp"
#include "trajectory_layout.hpp"

namespace dc {
namespace {

/// Buffered state values before they are appended: bounds the memory (a 40,000-body state is
/// 1.9 MB) while keeping the number of HDF5 calls per step small for small scenes.
constexpr std::size_t kBufferValues = std::size_t{1} << 17;  // 1 MiB of position doubles (≈ 4 MiB in all)

constexpr H5DatasetOptions kBulk{.extendible = true, .chunk_rows = 0, .deflate = 4};
constexpr H5DatasetOptions kStates{.extendible = true, .chunk_rows = 0, .deflate = 4, .extendible_columns = true};
constexpr H5DatasetOptions kPerStep{.extendible = true, .chunk_rows = 1024};

template <class T>
void append(H5File& f, const char* path, std::vector<T>& rows) {
  if (!rows.empty()) f.append_rows<T>(path, rows);
  rows.clear();
}

}  // namespace

TrajectoryWriter::TrajectoryWriter(std::string path, const World& world, const std::string& scene,
                                   const std::string& warmstart)
    : path_(std::move(path)), tmp_(path_ + ".tmp") {
  file_ = std::make_unique<H5File>(H5File::create(tmp_));
  H5File& f = *file_;
  n_ = world.bodies().size();
  const hsize_t n = n_;
  trajectory::write_attributes(f, scene, warmstart);
  f.create_dataset<double>("/bodies/position", {0, n, 2}, kStates);
  f.create_dataset<double>("/bodies/angle", {0, n}, kStates);
  f.create_dataset<double>("/bodies/velocity", {0, n, 2}, kStates);
  f.create_dataset<double>("/bodies/omega", {0, n}, kStates);
  f.create_dataset<std::int64_t>("/contacts/step_offset", {0}, kPerStep);
  f.create_dataset<std::int32_t>("/contacts/body_a", {0}, kBulk);
  f.create_dataset<std::int32_t>("/contacts/body_b", {0}, kBulk);
  f.create_dataset<double>("/contacts/point", {0, 2}, kBulk);
  f.create_dataset<double>("/contacts/normal", {0, 2}, kBulk);
  f.create_dataset<double>("/contacts/gap", {0}, kBulk);
  f.create_dataset<double>("/contacts/lambda", {0, 2}, kBulk);
  f.create_dataset<std::int32_t>("/contacts/feature", {0}, kBulk);
  f.create_dataset<std::int32_t>("/solver/sweeps", {0}, kPerStep);
  f.create_dataset<std::int32_t>("/solver/status", {0}, kPerStep);
  f.create_dataset<double>("/solver/theta_final", {0}, kPerStep);
  f.create_dataset<double>("/solver/residual", {0}, kPerStep);
  f.create_dataset<double>("/solver/profile", {0, static_cast<hsize_t>(TrajectoryRecorder::kProfileWidth)}, kPerStep);
  f.set_attribute("/solver/profile", "columns", TrajectoryRecorder::kProfileColumns);
  f.set_attribute("/solver/profile", "units", "s");
  step_offset_.push_back(0);
  buffer_state(world.bodies());
}

TrajectoryWriter::~TrajectoryWriter() {
  if (committed_) return;
  try {
    if (file_) file_->close();
  } catch (const std::exception&) {
    // a failed write was already reported; the temporary goes either way
  }
  file_.reset();
  std::error_code ignored;
  std::filesystem::remove(tmp_, ignored);
}

void TrajectoryWriter::buffer_state(const BodyState& s) {
  // Bodies are only ever appended (inflow.hpp): widen the state datasets (earlier states
  // read NaN there) and keep the tables of the latest state.
  if (s.size() < n_) throw InvalidArgument("TrajectoryWriter: the number of bodies decreased");
  if (s.size() != n_ || radius_.empty()) {
    if (s.size() != n_) {
      flush_buffers();  // buffered states have the old width
      H5File& f = *file_;
      const hsize_t rows = f.rows("/bodies/position"), n = s.size();
      f.resize("/bodies/position", {rows, n, 2});
      f.resize("/bodies/velocity", {rows, n, 2});
      f.resize("/bodies/angle", {rows, n});
      f.resize("/bodies/omega", {rows, n});
    }
    n_ = s.size();
    radius_.assign(s.radius.begin(), s.radius.end());
    mass_.assign(s.mass.begin(), s.mass.end());
    shapes_ = s.shapes;
  }
  for (std::size_t k = 0; k < n_; ++k) {
    position_.push_back(s.position[k].x);
    position_.push_back(s.position[k].y);
    angle_.push_back(s.angle[k]);
    velocity_.push_back(s.velocity[k].x);
    velocity_.push_back(s.velocity[k].y);
    omega_.push_back(s.omega[k]);
  }
  if (position_.size() + point_.size() >= kBufferValues) flush_buffers();
}

void TrajectoryWriter::record_step(const World& w, const StepReport& r, double record_seconds) {
  if (committed_) throw InvalidArgument(path_ + ": trajectory already committed");
  for (const Contact& c : w.contacts()) {
    body_a_.push_back(c.body_a);
    body_b_.push_back(c.body_b);
    point_.insert(point_.end(), {c.point.x, c.point.y});
    normal_.insert(normal_.end(), {c.normal.x, c.normal.y});
    gap_.push_back(c.gap);
    lambda_.insert(lambda_.end(), {c.lambda_n, c.lambda_t});
    feature_.push_back(c.key.feature);
  }
  contacts_ += static_cast<std::int64_t>(w.contacts().size());
  step_offset_.push_back(contacts_);
  sweeps_.push_back(r.solve.sweeps);
  status_.push_back(static_cast<std::int32_t>(r.solve.status));
  theta_final_.push_back(r.solve.theta.empty() ? 0.0 : r.solve.theta.back());
  residual_.push_back(r.solve.residual);
  const StepProfile& p = r.profile;
  profile_.insert(profile_.end(), {1e-3 * p.collide_ms, 1e-3 * p.assemble_ms, 1e-3 * p.warmstart_ms,
                                   1e-3 * p.solve_ms, 1e-3 * p.integrate_ms, record_seconds, 1e-3 * p.broad_phase_ms});
  ++steps_;
  buffer_state(w.bodies());
  if (steps_ % 256 == 0) flush_buffers();  // per-step rows of long runs of small scenes
}

void TrajectoryWriter::flush_buffers() {
  H5File& f = *file_;
  append(f, "/bodies/position", position_);
  append(f, "/bodies/angle", angle_);
  append(f, "/bodies/velocity", velocity_);
  append(f, "/bodies/omega", omega_);
  append(f, "/contacts/step_offset", step_offset_);
  append(f, "/contacts/body_a", body_a_);
  append(f, "/contacts/body_b", body_b_);
  append(f, "/contacts/point", point_);
  append(f, "/contacts/normal", normal_);
  append(f, "/contacts/gap", gap_);
  append(f, "/contacts/lambda", lambda_);
  append(f, "/contacts/feature", feature_);
  append(f, "/solver/sweeps", sweeps_);
  append(f, "/solver/status", status_);
  append(f, "/solver/theta_final", theta_final_);
  append(f, "/solver/residual", residual_);
  append(f, "/solver/profile", profile_);
}

void TrajectoryWriter::commit() { commit(path_); }

void TrajectoryWriter::commit(const std::string& target) {
  if (committed_) return;
  flush_buffers();
  trajectory::write_body_tables(*file_, n_, radius_, mass_, shapes_);
  file_->close();
  file_.reset();
  sync_path(tmp_);
  durable_rename(tmp_, target);
  committed_ = true;
}

}  // namespace dc
