// Names → solvers (make_solver, solver_names) and SolveStatus names.
#include <charconv>
#include <string>

#include "dc/core/error.hpp"
#include "dc/lcp/lcp_solver.hpp"
#include "dc/lcp/newton_sparse.hpp"
#include "dc/lcp/pgs_colored.hpp"
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
  }
  return "unknown";
}

std::vector<std::string> solver_names() {
  return {"pgs", "pgs-colored", "pgs-assembled", "psor", "jacobi", "lemke", "newton", "newton-sparse", "nncg"};
}

namespace {

/// "pgs-colored:<threads>[:<kernel>]": OpenMP threads ≥ 1, kernel auto|avx512|avx2|scalar.
PgsColoredDef pgs_colored_def(std::string_view name) {
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
  PgsColoredDef def;
  const auto [end, ec] = std::from_chars(t.data(), t.data() + t.size(), def.threads);
  if (ec != std::errc() || end != t.data() + t.size() || def.threads < 1) throw bad();
  if (colon == std::string_view::npos) return def;
  bool known = false;
  for (PgsColoredKernel kernel :
       {PgsColoredKernel::Auto, PgsColoredKernel::Avx512, PgsColoredKernel::Avx2, PgsColoredKernel::Scalar})
    if (k == to_string(kernel)) {
      def.kernel = kernel;
      known = true;
    }
  if (!known) throw bad();
  if (!pgs_colored_kernel_available(def.kernel))
    throw ConfigError("LCP solver '" + std::string(name) + "': this CPU cannot run the " + std::string(k) + " kernel");
  return def;
}

}  // namespace

std::unique_ptr<LcpSolver> make_solver(std::string_view name) {
  if (name == "pgs") return solvers::make_pgs_matrix_free();
  if (name == "pgs-colored") return solvers::make_pgs_colored();
  if (name.starts_with("pgs-colored:")) return make_pgs_colored(pgs_colored_def(name));
  if (name == "pgs-assembled") return solvers::make_pgs_assembled();
  if (name == "psor") return solvers::make_psor();
  if (name == "jacobi") return solvers::make_jacobi();
  if (name == "lemke") return solvers::make_lemke();
  if (name == "newton") return solvers::make_newton();
  if (name == "newton-sparse") return make_newton_sparse();
  if (name == "nncg") return solvers::make_nncg();
  std::string valid;
  for (const auto& n : solver_names()) valid += (valid.empty() ? "" : ", ") + n;
  throw ConfigError("unknown LCP solver '" + std::string(name) + "' (valid: " + valid + ")");
}

}  // namespace dc
