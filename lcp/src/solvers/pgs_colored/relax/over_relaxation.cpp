// pgs-colored's over-relaxation on the packed rows (over_relaxation.hpp).
#include "solvers/pgs_colored/relax/over_relaxation.hpp"

#include <limits>

#include "dc/core/number_text.hpp"

namespace dc::colored {
namespace {

/// j[s][k] ← ω·j[s][k] for the 6 slots, b[k] ← ω·b[k], over all W lanes.
inline void scale_row(double (*j)[W], double* b, double omega) {
  for (int s = 0; s < 6; ++s)
    for (int k = 0; k < W; ++k) j[s][k] *= omega;
  for (int k = 0; k < W; ++k) b[k] *= omega;
}

}  // namespace

void over_relax(Batch& B, double omega) {
  scale_row(B.jn, B.bn, omega);
  scale_row(B.jt, B.bt, omega);
}

void over_relax(PairBatch& P, double omega) {
  scale_row(P.jt0, P.bt0, omega);
  scale_row(P.jt1, P.bt1, omega);
}

SolveResult invalid_omega(const LcpProblem& p, const Eigen::VectorXd& lambda0, const SolverOptions& o) {
  SolveResult r;
  r.status = SolveStatus::InvalidInput;
  r.lambda = lambda0.size() == p.rows() && lambda0.allFinite() ? lambda0 : Eigen::VectorXd::Zero(p.rows());
  r.message = "pgs-colored: relaxation omega = " + g_text(o.omega) + " is outside (0, 2)";
  r.residual = std::numeric_limits<double>::infinity();
  return r;
}

}  // namespace dc::colored
