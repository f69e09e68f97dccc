#include "solvers/newton_sparse/sparse_factor.hpp"

#include <Eigen/CholmodSupport>
#include <Eigen/SparseCholesky>
#include <Eigen/SparseLU>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <optional>
#include <string>

#include "dc/core/error.hpp"

namespace dc::solvers {
namespace {

using ColMatrix = Eigen::SparseMatrix<double, Eigen::ColMajor, int>;
using Clock = std::chrono::steady_clock;

double ms_since(Clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
}

/// The benchmark switch DC_CHOLMOD (docs/solvers.md "CHOLMOD: simplicial or supernodal"):
/// "simplicial" or "supernodal" overrides the caller's choice for every factor made while it is
/// set (newton-sparse, prox-newton's body space, the proximal finish); unset or empty: the
/// caller's choice.
bool supernodal_choice(bool requested) {
  const char* env = std::getenv("DC_CHOLMOD");
  if (env == nullptr || *env == '\0') return requested;
  const std::string v(env);
  if (v == "supernodal") return true;
  if (v == "simplicial") return false;
  throw ConfigError("DC_CHOLMOD: '" + v + "' is neither 'simplicial' nor 'supernodal'");
}

/// Eigen's CHOLMOD decomposition with its factor reachable: solve() calls cholmod_solve2 on it
/// with kept workspace (Eigen's solve calls cholmod_solve, which allocates the answer and its
/// work vectors on every call and frees them again; cholmod_solve calls cholmod_solve2 with no
/// workspace, so the arithmetic and the bits are the same).
class Cholmod : public Eigen::CholmodDecomposition<ColMatrix, Eigen::Lower> {
 public:
  [[nodiscard]] cholmod_factor* factor() const { return m_cholmodFactor; }
};

}  // namespace

struct FreeBlockFactor::Impl {
  bool use_cholmod, reuse;
  // Pattern key: the compressed arrays of A and its symmetry at the last bind().
  std::vector<int> key_outer, key_inner;
  bool key_symmetric = true;
  bool pattern_ready = false;
  // P in column-major form (symmetric: lower triangle only), and for each stored entry the
  // index of the A value it copies (−1: a diagonal A does not store).
  ColMatrix P;
  std::vector<int> source;
  const SparseRowMatrix* A = nullptr;
  bool symmetric = true;
  bool analysed = false;
  // Factorisations (one is active after factorize()).
  Cholmod cholmod;
  // cholmod_solve2's answer and work vectors, kept from solve to solve (they are reallocated
  // by CHOLMOD only when the size changes); freed before the decomposition's cholmod_common.
  mutable cholmod_dense* solve_x = nullptr;
  mutable cholmod_dense* solve_y = nullptr;
  mutable cholmod_dense* solve_e = nullptr;

  Impl() = default;
  Impl(const Impl&) = delete;
  Impl& operator=(const Impl&) = delete;
  ~Impl() {
    cholmod_common& c = cholmod.cholmod();
    cholmod_free_dense(&solve_x, &c);
    cholmod_free_dense(&solve_y, &c);
    cholmod_free_dense(&solve_e, &c);
  }

  /// x = P⁻¹ r with the CHOLMOD factor; false when CHOLMOD failed.
  bool cholmod_solve(const Eigen::VectorXd& r, Eigen::VectorXd& x) const {
    cholmod_dense b{};
    b.nrow = static_cast<size_t>(r.size());
    b.ncol = 1;
    b.nzmax = b.nrow;
    b.d = b.nrow;
    b.x = const_cast<double*>(r.data());  // CHOLMOD reads B only
    b.xtype = CHOLMOD_REAL;
    b.dtype = CHOLMOD_DOUBLE;
    auto& c = const_cast<Cholmod&>(cholmod).cholmod();
    if (!cholmod_solve2(CHOLMOD_A, cholmod.factor(), &b, nullptr, &solve_x, nullptr, &solve_y, &solve_e, &c))
      return false;
    x = Eigen::Map<const Eigen::VectorXd>(static_cast<const double*>(solve_x->x), r.size());
    return true;
  }
  std::optional<Eigen::SimplicialLDLT<ColMatrix, Eigen::Lower>> ldlt;
  Eigen::SparseLU<ColMatrix> lu;
  enum class Active { None, Cholmod, Ldlt, Lu } active = Active::None;

  bool same_pattern(const SparseRowMatrix& a, bool sym) const {
    if (!pattern_ready || sym != key_symmetric) return false;
    if (static_cast<size_t>(a.outerSize() + 1) != key_outer.size()) return false;
    if (static_cast<size_t>(a.nonZeros()) != key_inner.size()) return false;
    return std::equal(key_outer.begin(), key_outer.end(), a.outerIndexPtr()) &&
           std::equal(key_inner.begin(), key_inner.end(), a.innerIndexPtr());
  }

  // P's pattern from A ∪ diag; each entry's value during construction is (A index + 1), so the
  // sum of duplicates (A's diagonal and the added one, which carries 0) recovers the index.
  void build_pattern(const SparseRowMatrix& a, bool sym) {
    const int n = static_cast<int>(a.rows());
    std::vector<Eigen::Triplet<double>> trip;
    trip.reserve(static_cast<size_t>(a.nonZeros() + n));
    for (int i = 0; i < n; ++i) {
      trip.emplace_back(i, i, 0.0);
      for (int k = a.outerIndexPtr()[i]; k < a.outerIndexPtr()[i + 1]; ++k) {
        const int j = a.innerIndexPtr()[k];
        if (sym && j < i) continue;  // lower triangle of P: row j ≥ column i (A is symmetric)
        if (sym) trip.emplace_back(j, i, k + 1.0);
        else trip.emplace_back(i, j, k + 1.0);
      }
    }
    P.resize(n, n);
    P.setFromTriplets(trip.begin(), trip.end());
    P.makeCompressed();
    source.resize(static_cast<size_t>(P.nonZeros()));
    for (Eigen::Index k = 0; k < P.nonZeros(); ++k) source[static_cast<size_t>(k)] = static_cast<int>(P.valuePtr()[k]) - 1;
    key_outer.assign(a.outerIndexPtr(), a.outerIndexPtr() + a.outerSize() + 1);
    key_inner.assign(a.innerIndexPtr(), a.innerIndexPtr() + a.nonZeros());
    key_symmetric = sym;
    pattern_ready = true;
    analysed = false;
  }

  void fill_values(const std::vector<char>& free, double rho) {
    const double* av = A->valuePtr();
    for (int c = 0; c < P.outerSize(); ++c) {
      for (int k = P.outerIndexPtr()[c]; k < P.outerIndexPtr()[c + 1]; ++k) {
        const int r = P.innerIndexPtr()[k];
        double v;
        if (free[static_cast<size_t>(r)] && free[static_cast<size_t>(c)]) {
          const int s = source[static_cast<size_t>(k)];
          v = (s >= 0 ? av[s] : 0.0) + (r == c ? rho : 0.0);
        } else {
          v = r == c ? 1.0 : 0.0;
        }
        P.valuePtr()[k] = v;
      }
    }
  }
};

FreeBlockFactor::FreeBlockFactor(bool use_cholmod, bool reuse_analysis, bool supernodal)
    : impl_(std::make_unique<Impl>()) {
  impl_->use_cholmod = use_cholmod;
  impl_->reuse = reuse_analysis;
  // Simplicial LDLᵀ needs no BLAS. Supernodal LLᵀ calls BLAS, and a multi-threaded BLAS
  // (Debian's OpenBLAS-pthread) on a loaded machine spends far more wall time than CPU time.
  impl_->cholmod.setMode(supernodal_choice(supernodal) ? Eigen::CholmodAuto : Eigen::CholmodLDLt);
}

FreeBlockFactor::~FreeBlockFactor() = default;

void FreeBlockFactor::bind(const SparseRowMatrix& A, bool symmetric) {
  Impl& m = *impl_;
  m.A = &A;
  m.symmetric = symmetric;
  if (!m.reuse || !m.same_pattern(A, symmetric)) {
    m.build_pattern(A, symmetric);
    m.active = Impl::Active::None;
  }
}

bool FreeBlockFactor::factored() const { return impl_->active != Impl::Active::None; }

bool FreeBlockFactor::factorize(const std::vector<char>& free, double rho, NewtonSparseStats& st) {
  Impl& m = *impl_;
  m.fill_values(free, rho);
  m.active = Impl::Active::None;
  if (!m.symmetric) {
    auto t0 = Clock::now();
    if (!m.analysed) {
      m.lu.analyzePattern(m.P);
      m.analysed = true;
      ++st.analyses;
      st.analyze_ms += ms_since(t0);
      t0 = Clock::now();
    }
    m.lu.factorize(m.P);
    ++st.factorizations;
    ++st.fallback_factorizations;
    st.factor_ms += ms_since(t0);
    if (m.lu.info() != Eigen::Success) return false;
    m.active = Impl::Active::Lu;
    return true;
  }
  if (m.use_cholmod) {
    auto t0 = Clock::now();
    if (!m.analysed) {
      m.cholmod.analyzePattern(m.P);
      m.analysed = true;
      ++st.analyses;
      st.analyze_ms += ms_since(t0);
      t0 = Clock::now();
    }
    m.cholmod.factorize(m.P);
    ++st.factorizations;
    st.factor_ms += ms_since(t0);
    if (m.cholmod.info() == Eigen::Success) {
      m.active = Impl::Active::Cholmod;
      return true;
    }
  }
  // Fallback (or the chosen path): Eigen's SimplicialLDLT, which tolerates tiny and negative
  // pivots that stop CHOLMOD's LLᵀ; analysed afresh each time (rarely taken).
  const auto t0 = Clock::now();
  m.ldlt.emplace();
  m.ldlt->compute(m.P);
  ++st.factorizations;
  ++st.fallback_factorizations;
  st.factor_ms += ms_since(t0);
  if (m.ldlt->info() != Eigen::Success) return false;
  m.active = Impl::Active::Ldlt;
  return true;
}

void FreeBlockFactor::solve(const Eigen::VectorXd& r, Eigen::VectorXd& x) const {
  const Impl& m = *impl_;
  switch (m.active) {
    case Impl::Active::Cholmod:
      if (!m.cholmod_solve(r, x)) x = Eigen::VectorXd::Constant(r.size(), std::nan(""));  // callers test finiteness
      break;
    case Impl::Active::Ldlt: x = m.ldlt->solve(r); break;
    case Impl::Active::Lu: x = m.lu.solve(r); break;
    case Impl::Active::None: x = r; break;  // not reached: callers factorise first
  }
}

}  // namespace dc::solvers
