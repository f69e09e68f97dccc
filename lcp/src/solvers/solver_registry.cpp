// Names ⇄ SolverId → solvers (make_solver, solver_names) and SolveStatus names.
#include <charconv>
#include <string>

#include "dc/core/error.hpp"
#include "dc/lcp/lcp_solver.hpp"
#include "dc/lcp/newton_sparse.hpp"
#include "dc/lcp/pgs_colored.hpp"
#include "dc/lcp/prox_newton.hpp"
#include "solvers/solvers.hpp"

namespace dc {

const char* to_string(SolveStatus s) {
  switch (s) {
    case SolveStatus::Converged: return "converged";
    case SolveStatus::SweepLimit: return "sweep_limit";
    case SolveStatus::Diverged: return "diverged";
    case SolveStatus::Infeasible: return "infeasible";
    case SolveStatus::Failed: return "failed";
    case SolveStatus::InvalidInput: return "invalid_input";
    case SolveStatus::ToleranceReached: return "tolerance_reached";
  }
  return "unknown";
}

namespace {

constexpr SolverKind kKinds[] = {SolverKind::Pgs,    SolverKind::PgsColored, SolverKind::PgsAssembled,
                                 SolverKind::Psor,   SolverKind::Jacobi,     SolverKind::Lemke,
                                 SolverKind::Newton, SolverKind::NewtonSparse, SolverKind::Nncg,
                                 SolverKind::ProxNewton, SolverKind::NncgColored};
constexpr PgsColoredKernel kKernels[] = {PgsColoredKernel::Auto, PgsColoredKernel::Avx512, PgsColoredKernel::Avx2,
                                         PgsColoredKernel::Scalar};

/// The suffix of "pgs-colored:<threads>[:<kernel>]": OpenMP threads ≥ 1, kernel auto|avx512|avx2|scalar.
SolverId pgs_colored_id(std::string_view name) {
  const auto bad = [&] {
    return ConfigError("LCP solver '" + std::string(name) +
                       "': expected pgs-colored:<threads>[:<kernel>], threads >= 1, kernel auto|avx512|avx2|scalar");
  };
  std::string_view t = name.substr(12), k;
  const size_t colon = t.find(':');
  if (colon != std::string_view::npos) {
    k = t.substr(colon + 1);
    t = t.substr(0, colon);
  }
  SolverId id{SolverKind::PgsColored};
  const auto [end, ec] = std::from_chars(t.data(), t.data() + t.size(), id.threads);
  if (ec != std::errc() || end != t.data() + t.size() || id.threads < 1) throw bad();
  if (colon == std::string_view::npos) return id;
  for (PgsColoredKernel kernel : kKernels)
    if (k == to_string(kernel)) id.kernel = kernel;
  if (!id.kernel) throw bad();
  return id;
}

}  // namespace

const char* to_string(SolverKind kind) {
  switch (kind) {
    case SolverKind::Pgs: return "pgs";
    case SolverKind::PgsColored: return "pgs-colored";
    case SolverKind::PgsAssembled: return "pgs-assembled";
    case SolverKind::Psor: return "psor";
    case SolverKind::Jacobi: return "jacobi";
    case SolverKind::Lemke: return "lemke";
    case SolverKind::Newton: return "newton";
    case SolverKind::NewtonSparse: return "newton-sparse";
    case SolverKind::Nncg: return "nncg";
    case SolverKind::ProxNewton: return "prox-newton";
    case SolverKind::NncgColored: return "nncg-colored";
  }
  return "unknown";
}

std::vector<std::string> solver_names() {
  std::vector<std::string> out;
  for (SolverKind k : kKinds) out.emplace_back(to_string(k));
  return out;
}

SolverId SolverId::parse(std::string_view name) {
  for (SolverKind k : kKinds)
    if (name == to_string(k)) return SolverId{k};
  if (name.starts_with("pgs-colored:")) return pgs_colored_id(name);
  std::string valid;
  for (const auto& n : solver_names()) valid += (valid.empty() ? "" : ", ") + n;
  throw ConfigError("unknown LCP solver '" + std::string(name) + "' (valid: " + valid + ")");
}

std::string to_string(const SolverId& id) {
  std::string out = to_string(id.kind);
  if (id.kind != SolverKind::PgsColored || id.threads == 0) return out;
  out += ":" + std::to_string(id.threads);
  if (id.kernel) out += std::string(":") + to_string(*id.kernel);
  return out;
}

std::unique_ptr<LcpSolver> make_solver(const SolverId& id) {
  switch (id.kind) {
    case SolverKind::Pgs: return solvers::make_pgs_matrix_free();
    case SolverKind::PgsColored: {
      if (id.threads == 0) return solvers::make_pgs_colored();
      PgsColoredDef def;
      def.threads = id.threads;
      def.kernel = id.kernel.value_or(PgsColoredKernel::Auto);
      if (!pgs_colored_kernel_available(def.kernel))
        throw ConfigError("LCP solver '" + to_string(id) + "': this CPU cannot run the " + to_string(def.kernel) +
                          " kernel");
      return make_pgs_colored(def);
    }
    case SolverKind::PgsAssembled: return solvers::make_pgs_assembled();
    case SolverKind::Psor: return solvers::make_psor();
    case SolverKind::Jacobi: return solvers::make_jacobi();
    case SolverKind::Lemke: return solvers::make_lemke();
    case SolverKind::Newton: return solvers::make_newton();
    case SolverKind::NewtonSparse: return make_newton_sparse();
    case SolverKind::Nncg: return solvers::make_nncg();
    case SolverKind::ProxNewton: return make_prox_newton();
    case SolverKind::NncgColored: return make_nncg_colored();
  }
  throw ConfigError("make_solver: invalid SolverKind " + std::to_string(static_cast<int>(id.kind)));
}

std::unique_ptr<LcpSolver> make_solver(std::string_view name) { return make_solver(SolverId::parse(name)); }

}  // namespace dc
