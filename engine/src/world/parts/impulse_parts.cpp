#include "world/parts/impulse_parts.hpp"

#include <algorithm>
#include <span>
#include <thread>
#include <vector>

#include "world/parts/step_parts.hpp"

namespace dc {
namespace {

/// True when rows r and r + 1 hold the same columns, strictly ascending (a contact's normal
/// and tangent rows as the assembly writes them).
bool same_columns(const int* outer, const int* inner, int r) {
  const int b = outer[r], e = outer[r + 1];
  if (outer[r + 2] - e != e - b) return false;
  bool same = true;
  for (int k = b; k < e; ++k) same &= inner[k] == inner[k - b + e] && (k + 1 == e || inner[k] < inner[k + 1]);
  return same;
}

/// Rows [first, rows) of Jᵀλ added into out. The rows are sorted by body a; the other body's dofs
/// are anywhere unless the bodies follow space, so the last column of the row kAhead rows on is
/// fetched early (a hint). Two rows with the same columns (a contact's normal and tangent rows)
/// are added column by column: each dof still receives its terms in row order (row r's, then
/// row r + 1's, no other row's between), so every sum is the row-by-row sum, bit for bit.
void add_rows(const SparseRowMatrix& J, const double* lambda, int first, int rows, double* out) {
  const int* const outer = J.outerIndexPtr();
  const int* const inner = J.innerIndexPtr();
  const double* const value = J.valuePtr();
  constexpr int kAhead = 8;
  const auto prefetch = [&](int r) {
    if (r + kAhead < rows && outer[r + kAhead + 1] > outer[r + kAhead])
      __builtin_prefetch(out + inner[outer[r + kAhead + 1] - 1], 1);
  };
  for (int r = first; r < rows;) {
    prefetch(r);
    const int b = outer[r], e = outer[r + 1];
    if (r + 1 < rows && same_columns(outer, inner, r)) {
      prefetch(r + 1);
      const double l0 = lambda[r], l1 = lambda[r + 1];
      for (int k = b; k < e; ++k) {
        double& o = out[inner[k]];
        o += value[k] * l0;
        o += value[k - b + e] * l1;
      }
      r += 2;
    } else {
      const double l = lambda[r];
      for (int k = b; k < e; ++k) out[inner[k]] += value[k] * l;
      r += 1;
    }
  }
}

/// A job of the threaded product: bodies [k0, k1), rows [r0, r1) (those whose first column is
/// theirs), the rows of that block with a column beyond 3·k1 (in row order), and whether a
/// row of the block starts outside its columns (the split is then void).
/// One cache line at least each: jobs of different threads write their own.
struct alignas(64) ImpulseJob {
  int k0 = 0, k1 = 0, r0 = 0, r1 = 0;
  bool broken = false, helped = false;  // helped: a helper ran the first run's job
  std::vector<int> spill;
};

/// `jobs` jobs in storage kept by the calling thread (a step's thread): no allocation once it
/// has held that many jobs and their spill lists have grown.
std::span<ImpulseJob> impulse_jobs(int jobs) {
  thread_local std::vector<ImpulseJob> kept;
  if (kept.size() < static_cast<size_t>(jobs)) kept.resize(static_cast<size_t>(jobs));
  return {kept.data(), static_cast<size_t>(jobs)};
}

/// The entries of row r in columns [c0, c1) added into out (λ_r · J_rk for each).
inline void add_row_within(const int* outer, const int* inner, const double* value, const double* lambda, int r, int c0, int c1,
                           double* out) {
  const double l = lambda[r];
  for (int k = outer[r]; k < outer[r + 1]; ++k) {
    const int c = inner[k];
    if (c >= c0 && c < c1) out[c] += value[k] * l;
  }
}

/// First run of the split: job j's rows are checked to start in its columns; those reaching
/// beyond them listed (a compressed matrix's rows hold ascending columns, so a row's first and
/// last columns bound the rest). False when some job found a row outside its columns, or when
/// the calling thread ran every job and !alone_ok (no helper came: the serial product then costs
/// less than the jobs' second run alone on it).
bool list_spills(const SparseRowMatrix& J, std::span<ImpulseJob> job, int threads, bool alone_ok) {
  const int* const outer = J.outerIndexPtr();
  const int* const inner = J.innerIndexPtr();
  const std::thread::id caller = std::this_thread::get_id();
  run_parts(threads, static_cast<int>(job.size()), [&](int p) {
    ImpulseJob& jb = job[static_cast<size_t>(p)];
    jb.helped = std::this_thread::get_id() != caller;
    std::vector<int>& spill = jb.spill;
    spill.clear();
    const int c0 = 3 * jb.k0, c1 = 3 * jb.k1;
    bool broken = false;
    for (int r = jb.r0; r < jb.r1; ++r) {
      const int b = outer[r], e = outer[r + 1];
      if (b == e) continue;
      broken |= (inner[b] < c0) | (inner[b] >= c1);
      if (inner[e - 1] >= c1) spill.push_back(r);
    }
    jb.broken = broken;
  });
  bool helped = false;
  for (const ImpulseJob& jb : job) {
    if (jb.broken) return false;
    helped = helped || jb.helped;
  }
  return helped || alone_ok;
}

/// Whether a sample of each job's rows (but the last job's) finds many that reach later jobs:
/// bodies numbered without regard to space (creation order), where the later jobs would read
/// most of the earlier blocks again and the split costs about what it spreads. kSpreadSample
/// rows evenly over each block; more than 1 in kSpreadRatio reaching past it is spread out.
bool spread_out(const SparseRowMatrix& J, std::span<const ImpulseJob> job) {
  constexpr int kSpreadSample = 32, kSpreadRatio = 8;
  const int* const outer = J.outerIndexPtr();
  const int* const inner = J.innerIndexPtr();
  for (size_t p = 0; p + 1 < job.size(); ++p) {
    const ImpulseJob& jb = job[p];
    const long span = jb.r1 - jb.r0;
    if (span <= 0) continue;
    int reach = 0;
    for (int i = 0; i < kSpreadSample; ++i) {
      const int r = jb.r0 + static_cast<int>(span * i / kSpreadSample);
      reach += outer[r + 1] > outer[r] && inner[outer[r + 1] - 1] >= 3 * jb.k1 ? 1 : 0;
    }
    if (reach * kSpreadRatio > kSpreadSample) return true;
  }
  return false;
}

/// contact_impulse on threads (see the header); false, with nothing written, when J's rows are
/// not laid out for the split or the bodies are too few for more than one job.
bool contact_impulse_split(const SparseRowMatrix& J, const double* lambda, double dt, Eigen::VectorXd& impulse, ColumnsDone done,
                           int threads, bool alone_ok) {
  const int rows = static_cast<int>(J.rows()), cols = static_cast<int>(J.cols());
  if (!J.isCompressed() || cols % 3 != 0 || rows == 0) return false;
  const int n = cols / 3;
  const int jobs = parts_for(threads, n, 1, 1024);  // one a thread: each job scans the earlier ones' spills
  if (jobs <= 1) return false;
  const int* const outer = J.outerIndexPtr();
  const int* const inner = J.innerIndexPtr();
  const double* const value = J.valuePtr();
  // The leading short rows (wall contacts: one body), then blocks of rows by their first body,
  // cut at the rows that split the rest evenly (so the jobs get alike work), each moved to the
  // first row of its body.
  const auto row_len = [&](int r) { return outer[r + 1] - outer[r]; };
  int w = 0;
  for (int lo = 0, hi = rows; lo < hi;) {  // partition point of "fewer than 6 entries"
    const int mid = lo + (hi - lo) / 2;
    if (row_len(mid) < 6) lo = w = mid + 1; else hi = mid;
  }
  const auto first_body = [&](int r) { return row_len(r) > 0 ? inner[outer[r]] / 3 : 0; };
  const std::span<ImpulseJob> job = impulse_jobs(jobs);
  job[0].k0 = 0;
  job[0].r0 = w;
  for (int p = 1; p < jobs; ++p) {
    const int q = static_cast<int>(w + static_cast<long>(rows - w) * p / jobs);
    const int k = std::max(job[static_cast<size_t>(p) - 1].k0, q < rows ? first_body(q) : n);
    int at = w;  // the first row of [w, rows) whose first body is k or later
    for (int lo = w, hi = rows; lo < hi;) {
      const int mid = lo + (hi - lo) / 2;
      if (first_body(mid) < k) lo = at = mid + 1; else hi = mid;
    }
    job[static_cast<size_t>(p)].k0 = k;
    job[static_cast<size_t>(p)].r0 = std::max(job[static_cast<size_t>(p) - 1].r0, at);
    job[static_cast<size_t>(p) - 1].k1 = k;
    job[static_cast<size_t>(p) - 1].r1 = job[static_cast<size_t>(p)].r0;
  }
  job[static_cast<size_t>(jobs) - 1].k1 = n;
  job[static_cast<size_t>(jobs) - 1].r1 = rows;
  if (!alone_ok && spread_out(J, job)) return false;
  if (!list_spills(J, job, threads, alone_ok)) return false;
  impulse.resize(cols);
  double* const out = impulse.data();
  run_parts(threads, jobs, [&](int p) {
    const ImpulseJob& jb = job[static_cast<size_t>(p)];
    const int c0 = 3 * jb.k0, c1 = 3 * jb.k1;
    std::fill(out + c0, out + c1, 0.0);
    for (int r = 0; r < w; ++r) add_row_within(outer, inner, value, lambda, r, c0, c1, out);
    for (int q = 0; q < p; ++q)
      for (const int r : job[static_cast<size_t>(q)].spill) add_row_within(outer, inner, value, lambda, r, c0, c1, out);
    // The block: every column ≥ c0 (checked); its listed rows also reach later jobs' columns.
    int r = jb.r0;
    for (const int s : jb.spill) {
      add_rows(J, lambda, r, s, out);
      add_row_within(outer, inner, value, lambda, s, c0, c1, out);
      r = s + 1;
    }
    add_rows(J, lambda, r, jb.r1, out);
    for (int c = c0; c < c1; ++c) out[c] *= dt;
    done(c0, c1);
  });
  return true;
}

}  // namespace

void contact_impulse(const SparseRowMatrix& J, const Eigen::Ref<const Eigen::VectorXd>& lambda, double dt, Eigen::VectorXd& impulse,
                     ColumnsDone done, int threads, ImpulseSplit split) {
  if (threads > 1 && contact_impulse_split(J, lambda.data(), dt, impulse, done, threads, split == ImpulseSplit::Always)) return;
  const int cols = static_cast<int>(J.cols());
  if (!J.isCompressed()) {
    impulse = J.transpose() * lambda * dt;
  } else {
    impulse.setZero(cols);
    add_rows(J, lambda.data(), 0, static_cast<int>(J.rows()), impulse.data());
    impulse *= dt;
  }
  done(0, cols);
}

}  // namespace dc
