// The products with J around pgs-colored's sweeps, on threads and bit-identical to the serial
// forms (pgs_colored_products.hpp).
#include "solvers/pgs_colored/pgs_colored_products.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#if defined(_OPENMP)
#include <omp.h>
#endif

#include "solvers/pgs_colored/pgs_colored_batch.hpp"

namespace dc::colored {
namespace {

int thread_id() {
#if defined(_OPENMP)
  return omp_get_thread_num();
#else
  return 0;
#endif
}

int team_size() {
#if defined(_OPENMP)
  return omp_get_num_threads();
#else
  return 1;
#endif
}

/// The first of n rows in thread t's chunk of nt (contiguous chunks in row order).
int chunk_begin(int n, int t, int nt) { return static_cast<int>(static_cast<long>(n) * t / nt); }

}  // namespace

void build_body_rows(const LcpProblem& p, int bodies, int threads, BodyRows& out) {
  const int n = p.rows();
  const ContactConstraints& cons = p.constraints;
  const int nt_max = std::max(1, threads);
  out.ok = false;
  if (!p.J.isCompressed()) return;  // the storage ranges below assume compressed rows
  out.row_body.resize(2 * static_cast<size_t>(n));
  out.split.resize(static_cast<size_t>(n));
  out.start.resize(static_cast<size_t>(bodies) + 1);
  out.cursor.assign(static_cast<size_t>(nt_max) * static_cast<size_t>(bodies), 0);
  const int* outer = p.J.outerIndexPtr();
  const int* inner = p.J.innerIndexPtr();
  bool unordered = false;
#pragma omp parallel num_threads(nt_max) if (nt_max > 1) reduction(|| : unordered)
  {
    // 1. Each row's bodies (the lower one first; a wall contact: its body, −1) and the storage
    // index where the other body's entries begin.
#pragma omp for schedule(static)
    for (int c = 0; c < cons.size(); ++c) {
      const ContactConstraint& k = cons[c];
      int first = k.body_b, second = -1;
      if (k.has_body_a() && k.body_a != k.body_b) {
        first = std::min(k.body_a, k.body_b);
        second = std::max(k.body_a, k.body_b);
      }
      for (const int r : {k.normal_row, k.tangent_row}) {
        if (r < 0) continue;
        out.row_body[2 * static_cast<size_t>(r)] = first;
        out.row_body[2 * static_cast<size_t>(r) + 1] = second;
        const int end = outer[r + 1];
        int split = end;
        for (int e = outer[r]; e < end; ++e) {
          const bool other = second >= 0 && inner[e] / 3 == second;
          if (other && split == end) split = e;
          unordered = unordered || (!other && split != end);
        }
        out.split[static_cast<size_t>(r)] = split;
      }
    }
    // 2. Per thread, how many rows of its chunk act on each body.
    const int t = thread_id(), nt = team_size();
    const int r0 = chunk_begin(n, t, nt), r1 = chunk_begin(n, t + 1, nt);
    int* cnt = out.cursor.data() + static_cast<size_t>(t) * static_cast<size_t>(bodies);
    for (int i = r0; i < r1; ++i)
      for (int s = 0; s < 2; ++s)
        if (const int b = out.row_body[2 * static_cast<size_t>(i) + s]; b >= 0) ++cnt[b];
#pragma omp barrier
    // 3. Rows per body, their offsets, and per (thread, body) the first slot of the chunk's rows:
    // chunks are in row order, so the concatenation is ascending.
#pragma omp for schedule(static)
    for (int b = 0; b < bodies; ++b) {
      int sum = 0;
      for (int u = 0; u < nt; ++u) sum += out.cursor[static_cast<size_t>(u) * bodies + b];
      out.start[static_cast<size_t>(b) + 1] = sum;
    }
#pragma omp single
    {
      out.start[0] = 0;
      for (int b = 0; b < bodies; ++b) out.start[static_cast<size_t>(b) + 1] += out.start[static_cast<size_t>(b)];
      out.rows.resize(static_cast<size_t>(out.start[static_cast<size_t>(bodies)]));
    }
#pragma omp for schedule(static)
    for (int b = 0; b < bodies; ++b) {
      int run = out.start[static_cast<size_t>(b)];
      for (int u = 0; u < nt; ++u) {
        int& c = out.cursor[static_cast<size_t>(u) * bodies + b];
        const int count = c;
        c = run;
        run += count;
      }
    }
    // 4. Fill, each thread its chunk in row order.
    for (int i = r0; i < r1; ++i)
      for (int s = 0; s < 2; ++s)
        if (const int b = out.row_body[2 * static_cast<size_t>(i) + s]; b >= 0) out.rows[static_cast<size_t>(cnt[b]++)] = i;
  }
  out.ok = !unordered;
}

void velocity_change(const LcpProblem& p, const BodyRows& br, const Eigen::VectorXd& lambda, int threads,
                     double* du) {
  const int bodies = static_cast<int>(br.start.size()) - 1;
  const int ncols = static_cast<int>(p.J.cols());
  const double* im = p.inv_mass.data();
  const double dt = p.dt;
#pragma omp parallel for num_threads(std::max(1, threads)) schedule(static) if (threads > 1)
  for (int k = 0; k < bodies; ++k) {
    // As Eigen's Jᵀλ (column-major product): s_c = ((0 + J_i₁c·λ_i₁) + J_i₂c·λ_i₂) + …, i ascending.
    double s[3] = {0.0, 0.0, 0.0};
    const int c0 = 3 * k;
    const double* value = p.J.valuePtr();
    const int* inner = p.J.innerIndexPtr();
    const int* outer = p.J.outerIndexPtr();
    for (int e = br.start[static_cast<size_t>(k)]; e < br.start[static_cast<size_t>(k) + 1]; ++e) {
      const int i = br.rows[static_cast<size_t>(e)];
      const double li = lambda[i];
      const bool lower = br.row_body[2 * static_cast<size_t>(i)] == k;
      const int from = lower ? outer[i] : br.split[static_cast<size_t>(i)];
      const int to = lower ? br.split[static_cast<size_t>(i)] : outer[i + 1];
      for (int q = from; q < to; ++q) s[inner[q] - c0] += value[q] * li;
    }
    double* out = du + static_cast<size_t>(kStride) * k;
    for (int d = 0; d < 3; ++d) out[d] = c0 + d < ncols ? im[c0 + d] * s[d] * dt : 0.0;
    for (int d = 3; d < kStride; ++d) out[d] = 0.0;
  }
  std::fill(du + static_cast<size_t>(kStride) * bodies, du + static_cast<size_t>(kStride) * (bodies + 1), 0.0);
}

double natural_residual(const LcpProblem& p, const BodyRows& br, const Eigen::VectorXd& lambda, int threads,
                        double* du, bool& all_finite) {
  velocity_change(p, br, lambda, threads, du);
  const int n = p.rows();
  double r = 0.0;
  bool nan = false, nonfinite = false;
#pragma omp parallel for num_threads(std::max(1, threads)) schedule(static) if (threads > 1) \
    reduction(max : r) reduction(|| : nan, nonfinite)
  for (int i = 0; i < n; ++i) {
    // w_i = J_i Δu + b_i as Eigen's row-major product (storage order, from 0), then the natural map.
    double tmp = 0.0;
    for (SparseRowMatrix::InnerIterator it(p.J, i); it; ++it) {
      const int c = static_cast<int>(it.col());
      tmp += it.value() * du[static_cast<size_t>(kStride) * (c / 3) + c % 3];
    }
    const double w = tmp + p.b[i];
    const double l = p.lower(i, lambda), h = p.upper(i, lambda);
    const double e = std::abs(lambda[i] - std::clamp(lambda[i] - w, l, std::max(l, h)));
    nonfinite = nonfinite || !std::isfinite(lambda[i]);
    if (std::isnan(e)) {
      nan = true;
    } else {
      r = std::max(r, e);
    }
  }
  all_finite = !nonfinite;
  return nan ? std::numeric_limits<double>::infinity() : r;
}

}  // namespace dc::colored
