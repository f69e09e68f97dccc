#include "solvers/exact/lemke_pivoting.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

namespace dc::solvers {

LemkePivoting lemke_pivoting(const Eigen::MatrixXd& M, const Eigen::VectorXd& q, const Eigen::VectorXd& d,
                             int cap) {
  const int n = static_cast<int>(q.size());
  LemkePivoting r;
  r.z = Eigen::VectorXd::Zero(n);
  if (n == 0 || q.minCoeff() >= 0) {  // z = 0 is a solution
    r.outcome = LemkePivoting::Outcome::Solved;
    return r;
  }
  constexpr double kInf = std::numeric_limits<double>::infinity();
  const int cols = 2 * n + 2, z0col = 2 * n, rhs = 2 * n + 1;
  using Tableau = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;
  Tableau T = Tableau::Zero(n, cols);  // row-major: pivots are row operations
  T.leftCols(n).setIdentity();
  T.middleCols(n, n) = -M;
  T.col(z0col) = -d;
  T.col(rhs) = q;
  std::vector<int> basis(static_cast<size_t>(n));
  for (int i = 0; i < n; ++i) basis[static_cast<size_t>(i)] = i;  // w_i basic

  // A pivot updates only the columns where the pivot row is nonzero (x − f·0 = x): for
  // hundreds of pivots the tableau stays mostly zeros. `bound` ≥ max |T_ij| (the old bound plus
  // max|f|·max|pivot row| after a pivot); only when it leaves the finite range is the tableau
  // scanned. pivot() returns whether the tableau is finite.
  std::vector<int> nz;
  nz.reserve(static_cast<size_t>(cols));
  double bound = T.cwiseAbs().maxCoeff();
  auto pivot = [&](int row, int col) {
    const double piv = T(row, col);
    T.row(row) /= piv;
    double* pr = T.data() + static_cast<Eigen::Index>(row) * cols;
    nz.clear();
    double prow = 0.0, fmax = 0.0;
    for (int j = 0; j < cols; ++j)
      if (pr[j] != 0.0) {
        nz.push_back(j);
        prow = std::max(prow, std::abs(pr[j]));
      }
    for (int i = 0; i < n; ++i) {
      double* ri = T.data() + static_cast<Eigen::Index>(i) * cols;
      const double f = ri[col];
      if (i == row || f == 0.0) continue;
      fmax = std::max(fmax, std::abs(f));
      for (const int j : nz) ri[j] -= f * pr[j];
    }
    T.col(col).setZero();
    T(row, col) = 1.0;
    basis[static_cast<size_t>(row)] = col;
    bound = std::max(bound + fmax * prow, std::max(prow, 1.0));
    if (bound <= 1e300) return true;  // NaN compares false
    if (!T.allFinite()) return false;
    bound = T.cwiseAbs().maxCoeff();
    return true;
  };

  int first = 0;
  for (int i = 1; i < n; ++i)
    if (q[i] / d[i] < q[first] / d[first]) first = i;  // lowest index among ties
  int leaving = basis[static_cast<size_t>(first)];
  bool finite = pivot(first, z0col);
  r.pivots = 1;
  while (true) {
    if (r.pivots >= cap) {
      r.why = "pivot cap " + std::to_string(cap) + " reached";
      return r;
    }
    const int entering = leaving < n ? leaving + n : leaving - n;  // complement
    const Eigen::VectorXd col = T.col(entering);
    const double tol = 1e-12 * std::max(1.0, col.cwiseAbs().maxCoeff());
    int best = -1;
    double best_ratio = kInf;
    for (int i = 0; i < n; ++i) {
      if (col[i] <= tol) continue;
      const double ratio = T(i, rhs) / col[i];
      if (best < 0 || ratio < best_ratio - 1e-12 * std::max(1.0, std::abs(best_ratio))) {
        best = i;
        best_ratio = ratio;
      } else if (ratio <= best_ratio + 1e-12 * std::max(1.0, std::abs(best_ratio))) {
        // Tie: z₀ leaves first; otherwise lexicographic minimum of B⁻¹ rows / col_i.
        const bool i_z0 = basis[static_cast<size_t>(i)] == z0col;
        const bool b_z0 = basis[static_cast<size_t>(best)] == z0col;
        if (b_z0) continue;
        if (i_z0) {
          best = i;
          best_ratio = std::min(best_ratio, ratio);
          continue;
        }
        for (int j = 0; j < n; ++j) {
          const double a = T(i, j) / col[i], b = T(best, j) / col[best];
          if (a < b - 1e-14) {
            best = i;
            best_ratio = std::min(best_ratio, ratio);
            break;
          }
          if (a > b + 1e-14) break;
        }
      }
    }
    if (best < 0) {
      r.outcome = LemkePivoting::Outcome::Ray;
      r.why = "ray termination after " + std::to_string(r.pivots) + " pivots";
      return r;
    }
    leaving = basis[static_cast<size_t>(best)];
    finite = pivot(best, entering) && finite;
    ++r.pivots;
    if (!finite) {
      r.why = "tableau became non-finite";
      return r;
    }
    if (leaving == z0col) break;
  }
  r.outcome = LemkePivoting::Outcome::Solved;
  for (int i = 0; i < n; ++i) {
    const int v = basis[static_cast<size_t>(i)];
    if (v >= n && v < 2 * n) {
      r.z[v - n] = std::max(0.0, T(i, rhs));
      r.active.push_back(v - n);
    }
  }
  return r;
}

}  // namespace dc::solvers
