// DataSetWriter: appends simulations to a single-file data set in index order (rows first,
// /sims after, /sims/seed last, then flush; see data_set.hpp), and append_simulation, which
// also writes the one simulation of a shard (data_set_shards.cpp).
#include <filesystem>

#include "data_set_layout.hpp"
#include "dc/cnn/data_set.hpp"
#include "dc/core/error.hpp"

namespace dc {

namespace dataset {

void append_simulation(H5File& f, const SimulationRecord& r, int sim_id, RowCounts& at) {
  const std::size_t n = r.samples(), B = static_cast<std::size_t>(r.bodies), C = r.contacts();
  const bool varying = !r.body_count.empty();
  std::size_t body_rows = n * B;
  if (varying) {
    body_rows = 0;
    for (const auto b : r.body_count) body_rows += static_cast<std::size_t>(b);
  }
  if ((varying && r.body_count.size() != n) || r.contact_count.size() != n || r.residual.size() != n ||
      r.position.size() != 2 * body_rows || r.mass.size() != body_rows ||
      r.point.size() != 2 * C || r.lambda_star.size() != 2 * C || r.gap.size() != C || r.body_b.size() != C)
    throw InvalidArgument("data set: simulation " + std::to_string(r.index) + ": inconsistent record sizes");
  std::vector<std::int32_t> sim(n, sim_id), body_count = varying ? r.body_count : std::vector<std::int32_t>(n, r.bodies);
  std::vector<std::int64_t> body_begin(n), contact_begin(n);
  std::int64_t c0 = at.contact_rows, b0 = at.body_rows;
  for (std::size_t s = 0; s < n; ++s) {
    body_begin[s] = b0;
    b0 += body_count[s];
    contact_begin[s] = c0;
    c0 += r.contact_count[s];
  }
  // Appending zero rows is skipped (a simulation without contacts has no sample rows).
  const auto rows = [&]<class T>(const char* path, const std::vector<T>& v) {
    if (!v.empty()) f.append_rows<T>(path, v);
  };
  // 1. rows (any order among themselves; none is visible until /sims/seed grows)
  rows("/samples/sim", sim);
  rows("/samples/step", r.step);
  rows(kFeatures, r.features);
  rows(kLabels, r.labels);
  rows("/samples/body_begin", body_begin);
  rows("/samples/body_count", body_count);
  rows("/samples/contact_begin", contact_begin);
  rows("/samples/contact_count", r.contact_count);
  rows("/samples/residual", r.residual);
  rows("/bodies/position", r.position);
  rows("/bodies/velocity", r.velocity);
  rows("/bodies/omega", r.omega);
  rows("/bodies/angle", r.angle);
  rows("/bodies/radius", r.radius);
  rows("/bodies/mass", r.mass);
  rows("/contacts/body_a", r.body_a);
  rows("/contacts/body_b", r.body_b);
  rows("/contacts/point", r.point);
  rows("/contacts/normal", r.normal);
  rows("/contacts/gap", r.gap);
  rows("/contacts/lambda_star", r.lambda_star);
  // 2. the simulation's /sims row, seed LAST: it is what makes the simulation count.
  const std::int32_t bodies[] = {r.bodies};
  const std::int64_t samples[] = {static_cast<std::int64_t>(n)}, contacts[] = {static_cast<std::int64_t>(C)};
  const double residual[] = {r.max_residual};
  const std::int64_t seed[] = {static_cast<std::int64_t>(r.seed)};
  f.append_rows<std::int32_t>(kSimsBodies, bodies);
  f.append_rows<std::int64_t>(kSimsSamples, samples);
  f.append_rows<std::int64_t>(kSimsContacts, contacts);
  f.append_rows<double>(kSimsResidual, residual);
  f.append_rows<std::int64_t>(kSimsSeed, seed);
  ++at.completed;
  at.samples += static_cast<std::int64_t>(n);
  at.body_rows += static_cast<std::int64_t>(body_rows);
  at.contact_rows = c0;
}

}  // namespace dataset

using namespace dataset;

DataSetWriter::DataSetWriter(H5File file) : file_(std::move(file)) {}

DataSetWriter DataSetWriter::create(const std::string& path, const DataSetParams& params) {
  params.validate();
  DataSetWriter w(H5File::create(path));
  write_params(w.file_, params);
  create_layout(w.file_, params);
  w.file_.flush();
  return w;
}

DataSetWriter DataSetWriter::resume(const std::string& path, const DataSetParams& params) {
  params.validate();
  if (!std::filesystem::exists(path)) throw IoError(path + ": no interrupted data set to resume");
  DataSetWriter w(H5File::open_rw(path));
  H5File& f = w.file_;
  const DataSetParams stored = read_params(f);
  if (const std::string diff = first_difference(stored, params); !diff.empty())
    throw ConfigError(path + ": cannot resume: " + diff + " differs from the interrupted run");
  const RowCounts rows = committed_rows(f);
  // Cut every dataset back to what the completed simulations recorded; an interrupted
  // append may have left rows of the simulation that was being written.
  const auto cut = [&](const char* p, std::int64_t n) {
    if (!f.is_dataset(p)) throw IoError(path + ": " + p + ": missing (truncated data set)");
    if (static_cast<std::int64_t>(f.rows(p)) < n)
      throw IoError(path + ": " + p + ": has " + std::to_string(f.rows(p)) + " rows, the completed " +
                    "simulations need " + std::to_string(n) + " (truncated data set)");
    f.resize_rows(p, static_cast<hsize_t>(n));
  };
  for (const char* p : {"/samples/sim", "/samples/step", kFeatures, kLabels, "/samples/body_begin",
                        "/samples/body_count", "/samples/contact_begin", "/samples/contact_count",
                        "/samples/residual"})
    cut(p, rows.samples);
  for (const char* p : {"/bodies/position", "/bodies/velocity", "/bodies/omega", "/bodies/angle", "/bodies/radius",
                        "/bodies/mass"})
    cut(p, rows.body_rows);
  for (const char* p : {"/contacts/body_a", "/contacts/body_b", "/contacts/point", "/contacts/normal",
                        "/contacts/gap", "/contacts/lambda_star"})
    cut(p, rows.contact_rows);
  for (const char* p : {kSimsBodies, kSimsSamples, kSimsContacts, kSimsResidual, kSimsSeed}) cut(p, rows.completed);
  f.flush();
  w.completed_ = rows.completed;
  w.samples_ = rows.samples;
  w.body_rows_ = rows.body_rows;
  w.contact_rows_ = rows.contact_rows;
  return w;
}

void DataSetWriter::append(const SimulationRecord& r) {
  if (r.index != completed_)
    throw InvalidArgument("DataSetWriter::append: simulation " + std::to_string(r.index) +
                          " handed in, but the next to write is " + std::to_string(completed_));
  RowCounts at{completed_, samples_, body_rows_, contact_rows_};
  append_simulation(file_, r, r.index, at);
  file_.flush();
  completed_ = at.completed;
  samples_ = at.samples;
  body_rows_ = at.body_rows;
  contact_rows_ = at.contact_rows;
}

void DataSetWriter::close() {
  if (file_.is_open()) {
    file_.flush();
    file_.close();
  }
}

}  // namespace dc
