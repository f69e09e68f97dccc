#include "dc/lcp/problem_file.hpp"

#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>
#include <string_view>

#include "dc/core/error.hpp"
#include "dc/lcp/dat_file.hpp"
#include "dc/lcp/fc2d_dat_file.hpp"
#include "formats/dat_tokens.hpp"

namespace dc {
namespace {

/// True when the file starts with HDF5's signature (a superblock at offset 0, as every file
/// HDF5 writes without a user block has). Only a regular file is looked into: HDF5 reads only
/// those, and peeking into a pipe would consume what the .dat reader needs (or, for a FIFO
/// with no writer, wait forever).
bool is_hdf5(const std::string& path) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec)) return false;
  std::ifstream in(path, std::ios::binary);
  char head[8] = {};
  in.read(head, 8);
  return in.gcount() == 8 && std::memcmp(head, "\x89HDF\r\n\x1a\n", 8) == 0;
}

Eigen::VectorXd to_vector(const std::vector<double>& v) {
  return Eigen::Map<const Eigen::VectorXd>(v.data(), static_cast<Eigen::Index>(v.size()));
}

FclibSolution solution_of(const Fc2dProblem& p, const Eigen::VectorXd& r) {
  if (r.size() != p.q.size())
    throw InvalidArgument("write_fc2d_problem: a solution or guess has " + std::to_string(r.size()) +
                          " entries, the problem " + std::to_string(p.q.size()));
  const Eigen::VectorXd u = p.W * r + p.q;
  return {std::vector<double>(r.data(), r.data() + r.size()), std::vector<double>(u.data(), u.data() + u.size())};
}

}  // namespace

const char* to_string(ProblemKind k) { return k == ProblemKind::Lcp ? "lcp" : "fc2d"; }

ProblemKind parse_problem_kind(const std::string& name) {
  if (name == "lcp") return ProblemKind::Lcp;
  if (name == "fc2d") return ProblemKind::Fc2d;
  throw ConfigError("problem kind '" + name + "' is not one of lcp, fc2d");
}

const char* to_string(ProblemFormat f) {
  switch (f) {
    case ProblemFormat::SiconosLcp: return "siconos-lcp";
    case ProblemFormat::SiconosFc: return "siconos-fc";
    case ProblemFormat::Fclib: return "fclib";
  }
  return "?";
}

ProblemFormat parse_problem_format(const std::string& name) {
  for (ProblemFormat f : {ProblemFormat::SiconosLcp, ProblemFormat::SiconosFc, ProblemFormat::Fclib})
    if (name == to_string(f)) return f;
  throw ConfigError("format '" + name + "' is not one of siconos-lcp, siconos-fc, fclib");
}

Fc2dProblem fc2d_from_fclib(const FclibLocalProblem& f) {
  Fc2dProblem p;
  std::vector<Eigen::Triplet<double, int>> trip;
  trip.reserve(f.values.size());
  for (int j = 0; j < f.rows; ++j)
    for (std::int32_t k = f.col_start[static_cast<size_t>(j)]; k < f.col_start[static_cast<size_t>(j) + 1]; ++k)
      trip.emplace_back(f.row_index[static_cast<size_t>(k)], j, f.values[static_cast<size_t>(k)]);
  p.W.resize(f.rows, f.rows);
  p.W.setFromTriplets(trip.begin(), trip.end());
  p.q = to_vector(f.q);
  p.mu = to_vector(f.mu);
  return p;
}

FclibLocalProblem fclib_from_fc2d(const Fc2dProblem& p) {
  p.validate();
  const Eigen::SparseMatrix<double, Eigen::ColMajor, int> W = p.W;  // compressed columns
  FclibLocalProblem f;
  f.rows = static_cast<int>(p.q.size());
  f.col_start.push_back(0);
  for (int j = 0; j < f.rows; ++j) {
    for (Eigen::SparseMatrix<double, Eigen::ColMajor, int>::InnerIterator it(W, j); it; ++it)
      if (it.value() != 0.0) {
        f.row_index.push_back(static_cast<std::int32_t>(it.row()));
        f.values.push_back(it.value());
      }
    f.col_start.push_back(static_cast<std::int32_t>(f.values.size()));
  }
  f.q.assign(p.q.data(), p.q.data() + p.q.size());
  f.mu.assign(p.mu.data(), p.mu.data() + p.mu.size());
  return f;
}

ProblemFile read_problem_file(const std::string& path, std::optional<ProblemKind> force) {
  ProblemFile out;
  if (is_hdf5(path)) {
    if (force == ProblemKind::Lcp)
      throw ConfigError(path + ": an FCLIB file holds a frictional problem (--kind lcp does not apply)");
    const FclibLocalProblem f = read_fclib_local(path);
    out.kind = ProblemKind::Fc2d;
    out.format = ProblemFormat::Fclib;
    out.fc2d = fc2d_from_fclib(f);
    if (f.solution) out.solution = to_vector(f.solution->r);
    for (const FclibSolution& g : f.guesses) out.guesses.push_back(to_vector(g.r));
  } else {
    // Bounded by the file's size, or kMaxDatStreamBytes for a pipe or device.
    const std::string text = dat::read_whole_file(path, "problem file");
    out.kind = force ? *force : detect_dat_kind(text, path) == DatKind::Fc2d ? ProblemKind::Fc2d : ProblemKind::Lcp;
    if (out.kind == ProblemKind::Lcp) {
      DatFile d = parse_dat_file(text, path);
      out.lcp = std::move(d.problem);
      out.comment = std::move(d.comment);
      return out;
    }
    Fc2dDatFile d = parse_fc2d_dat(text, path);
    out.format = ProblemFormat::SiconosFc;
    out.fc2d = std::move(d.problem);
    out.comment = std::move(d.comment);
  }
  out.lcp = fc2d_to_lcp(out.fc2d);
  return out;
}

void write_fc2d_problem(const std::string& path, const Fc2dProblem& p, ProblemFormat format,
                        const Eigen::VectorXd& solution, const std::vector<Eigen::VectorXd>& guesses) {
  if (format == ProblemFormat::SiconosFc) {
    write_fc2d_dat(path, p, Fc2dStorage::SparseBlock);
    return;
  }
  if (format != ProblemFormat::Fclib)
    throw InvalidArgument("write_fc2d_problem: a frictional problem is written as fclib or siconos-fc");
  FclibLocalProblem f = fclib_from_fc2d(p);
  if (solution.size() > 0) f.solution = solution_of(p, solution);
  for (const Eigen::VectorXd& g : guesses) f.guesses.push_back(solution_of(p, g));
  write_fclib_local(path, f);
}

ProblemFormat problem_format_for_path(const std::string& path, ProblemKind kind) {
  const auto ends_with = [&](const char* tail) { return std::string_view(path).ends_with(tail); };
  if (ends_with(".hdf5") || ends_with(".h5")) return ProblemFormat::Fclib;
  return kind == ProblemKind::Fc2d ? ProblemFormat::SiconosFc : ProblemFormat::SiconosLcp;
}

void write_problem_file(const std::string& path, const ProblemFile& file, const ProblemWriteDef& def) {
  if (def.storage != 0 && def.storage != 1) throw ConfigError("storage must be 0 (dense) or 1 (sparse block)");
  if (def.block < 0) throw ConfigError("block must be >= 1");
  const ProblemFormat format = def.format ? *def.format : problem_format_for_path(path, file.kind);
  if (format == ProblemFormat::SiconosLcp) {
    if (file.kind == ProblemKind::Fc2d)
      throw ConfigError(path + ": a frictional problem is written as siconos-fc or FCLIB (.hdf5), not as an LCP .dat");
    if (def.storage == 0)
      write_lcp_dat(path, Eigen::MatrixXd(file.lcp.A), Eigen::VectorXd(file.lcp.b));
    else
      write_lcp_dat_blocks(path, file.lcp.A, Eigen::VectorXd(file.lcp.b), def.block > 0 ? def.block : file.lcp.rows());
    return;
  }
  if (file.kind != ProblemKind::Fc2d)
    throw ConfigError(path + ": an LCP has no friction; only frictional problems are written as " + to_string(format));
  write_fc2d_problem(path, file.fc2d, format, file.solution, file.guesses);
}

}  // namespace dc
