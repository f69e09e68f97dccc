#include "dc/lcp/fc2d_problem.hpp"

#include <cmath>
#include <limits>
#include <string>

#include "dc/core/error.hpp"
#include "dc/core/number_text.hpp"

namespace dc {

void Fc2dProblem::validate() const {
  const long long nc = mu.size();
  if (nc < 1) throw InvalidArgument("frictional-contact problem: it has no contact");
  if (W.rows() != 2 * nc || W.cols() != 2 * nc || q.size() != 2 * nc)
    throw InvalidArgument("frictional-contact problem: W is " + std::to_string(W.rows()) + "x" +
                          std::to_string(W.cols()) + " and q has " + std::to_string(q.size()) + " entries, but " +
                          std::to_string(nc) + " contacts need " + std::to_string(2 * nc));
  for (int k = 0; k < W.outerSize(); ++k)
    for (SparseRowMatrix::InnerIterator it(W, k); it; ++it)
      if (!std::isfinite(it.value()))
        throw InvalidArgument("frictional-contact problem: W(" + std::to_string(it.row()) + "," +
                              std::to_string(it.col()) + ") is not finite");
  if (!q.allFinite()) throw InvalidArgument("frictional-contact problem: q has a non-finite entry");
  for (long long c = 0; c < nc; ++c)
    if (!(mu[c] >= 0) || !std::isfinite(mu[c]))
      throw InvalidArgument("frictional-contact problem: mu of contact " + std::to_string(c) + " is " +
                            g_text(mu[c]) + " (must be finite and >= 0)");
}

LcpProblem fc2d_to_lcp(const Fc2dProblem& p) {
  p.validate();
  LcpProblem out = LcpProblem::standard(p.W, p.q);
  for (int c = 0; c < p.contacts(); ++c) {
    const int t = 2 * c + 1;
    out.normal_row[static_cast<size_t>(t)] = 2 * c;
    out.mu[t] = p.mu[c];
    out.lo[t] = -std::numeric_limits<double>::infinity();  // ignored for friction rows
  }
  return out;
}

Fc2dFromLcp fc2d_from_lcp(const LcpProblem& p) {
  LcpProblem local = p;
  local.ensure_assembled_matrix();
  const int n = local.rows();
  // Contacts = normal rows; each friction row attaches to its normal row.
  std::vector<int> tangent_of(static_cast<size_t>(n), -1);
  std::vector<int> normals;
  for (int i = 0; i < n; ++i) {
    const int nr = local.normal_row[static_cast<size_t>(i)];
    if (nr >= 0) {
      if (tangent_of[static_cast<size_t>(nr)] >= 0)
        throw InvalidArgument("fc2d_from_lcp: normal row " + std::to_string(nr) + " has two friction rows (not 2D)");
      tangent_of[static_cast<size_t>(nr)] = i;
    } else if (local.lo[i] == 0.0 && local.hi[i] == std::numeric_limits<double>::infinity()) {
      normals.push_back(i);
    } else {
      throw InvalidArgument("fc2d_from_lcp: row " + std::to_string(i) +
                            " is neither a contact normal [0, inf) nor a friction row");
    }
  }
  const int nc = static_cast<int>(normals.size());
  Fc2dFromLcp out;
  out.lcp_row.assign(static_cast<size_t>(2 * nc), -1);
  out.problem.mu.setZero(nc);
  for (int c = 0; c < nc; ++c) {
    const int nr = normals[static_cast<size_t>(c)], tr = tangent_of[static_cast<size_t>(nr)];
    out.lcp_row[static_cast<size_t>(2 * c)] = nr;
    out.lcp_row[static_cast<size_t>(2 * c + 1)] = tr;
    if (tr >= 0) out.problem.mu[c] = local.mu[tr];
  }
  std::vector<int> fc_row(static_cast<size_t>(n), -1);  // inverse map
  for (int k = 0; k < 2 * nc; ++k)
    if (out.lcp_row[static_cast<size_t>(k)] >= 0) fc_row[static_cast<size_t>(out.lcp_row[static_cast<size_t>(k)])] = k;
  std::vector<Eigen::Triplet<double, int>> trip;
  trip.reserve(static_cast<size_t>(local.A.nonZeros()) + static_cast<size_t>(nc));
  out.problem.q.setZero(2 * nc);
  for (int i = 0; i < n; ++i) {
    const int fi = fc_row[static_cast<size_t>(i)];
    out.problem.q[fi] = local.b[i];
    for (SparseRowMatrix::InnerIterator it(local.A, i); it; ++it)
      if (it.value() != 0.0) trip.emplace_back(fi, fc_row[static_cast<size_t>(it.col())], it.value());
  }
  for (int c = 0; c < nc; ++c)  // decoupled tangent rows of frictionless contacts
    if (out.lcp_row[static_cast<size_t>(2 * c + 1)] < 0) {
      const double wnn = local.A.coeff(normals[static_cast<size_t>(c)], normals[static_cast<size_t>(c)]);
      trip.emplace_back(2 * c + 1, 2 * c + 1, wnn > 0 ? wnn : 1.0);
    }
  out.problem.W.resize(2 * nc, 2 * nc);
  out.problem.W.setFromTriplets(trip.begin(), trip.end());
  return out;
}

Eigen::VectorXd fc2d_reactions(const Fc2dFromLcp& map, const Eigen::VectorXd& lambda) {
  Eigen::VectorXd r = Eigen::VectorXd::Zero(static_cast<Eigen::Index>(map.lcp_row.size()));
  for (size_t k = 0; k < map.lcp_row.size(); ++k) {
    const int i = map.lcp_row[k];
    if (i >= 0) {
      if (i >= lambda.size()) throw InvalidArgument("fc2d_reactions: lambda is shorter than the problem");
      r[static_cast<Eigen::Index>(k)] = lambda[i];
    }
  }
  return r;
}

double fc2d_natural_residual(const Fc2dProblem& p, const Eigen::VectorXd& r) {
  return natural_residual(fc2d_to_lcp(p), r);
}

}  // namespace dc
