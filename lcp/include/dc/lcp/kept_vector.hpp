#pragma once
// Storage that keeps its capacity when its size changes, for the vectors a World refills every
// step (LcpProblem's b, lo, hi and μ, the kept warm start): an Eigen::VectorXd frees and
// allocates on every change of size (DenseStorage::resize), so a pile that gains rows every step
// would allocate each of them every step. KeptVector reallocates only to grow past its
// capacity, then to max(n, 2·capacity): a growing row count allocates O(log n) times in all.
#include <Eigen/Core>
#include <algorithm>
#include <new>

namespace dc {

/// A dense vector of doubles that reads and writes as an Eigen vector (it is an Eigen::Map over
/// the first size() entries of its storage: expressions, coefficients, data(), segments,
/// Eigen::Ref<const Eigen::VectorXd> without a copy) and keeps its storage across resize().
/// Assigning an Eigen expression sets the size and the values (as VectorXd does).
/// It is not an Eigen::VectorXd: binding it to a `const Eigen::VectorXd&` is a compile error
/// (it would copy into a temporary that a kept pointer would outlive); take an
/// Eigen::Ref<const Eigen::VectorXd>, or copy explicitly with Eigen::VectorXd(v).
class KeptVector : public Eigen::Map<Eigen::VectorXd> {
 public:
  using Base = Eigen::Map<Eigen::VectorXd>;

  KeptVector() noexcept : Base(nullptr, 0) {}
  KeptVector(const KeptVector& other) : KeptVector() { assign(other); }
  KeptVector(KeptVector&& other) noexcept : KeptVector() { swap(other); }
  /// The values of an Eigen expression (implicit, as `problem.b = vector` reads).
  template <class Derived>
  KeptVector(const Eigen::DenseBase<Derived>& values) : KeptVector() {  // NOLINT(google-explicit-constructor)
    assign(values);
  }
  KeptVector& operator=(const KeptVector& other) {
    if (this != &other) assign(other);
    return *this;
  }
  KeptVector& operator=(KeptVector&& other) noexcept {
    swap(other);
    return *this;
  }
  template <class Derived>
  KeptVector& operator=(const Eigen::DenseBase<Derived>& values) {
    assign(values);
    return *this;
  }
  ~KeptVector() = default;

  /// Size n; the values are unspecified after a change of size (as VectorXd::resize). Allocates
  /// only when n exceeds capacity().
  void resize(Eigen::Index n) {
    if (n > capacity()) store_.resize(grown(n));
    rebind(n);
  }
  /// Size n keeping the first min(n, size()) values (VectorXd::conservativeResize's name).
  void conservativeResize(Eigen::Index n) {
    if (n > capacity()) {
      Eigen::VectorXd bigger(grown(n));
      bigger.head(size()) = *this;
      store_.swap(bigger);
    }
    rebind(n);
  }
  void setZero() { Base::setZero(); }
  void setZero(Eigen::Index n) {
    resize(n);
    Base::setZero();
  }
  void setConstant(double value) { Base::setConstant(value); }
  void setConstant(Eigen::Index n, double value) {
    resize(n);
    Base::setConstant(value);
  }
  /// Entries held without a reallocation.
  [[nodiscard]] Eigen::Index capacity() const { return store_.size(); }
  /// Exchanges the storage (and the sizes) of two vectors; never allocates.
  void swap(KeptVector& other) noexcept {
    const Eigen::Index mine = size(), theirs = other.size();
    store_.swap(other.store_);
    rebind(theirs);
    other.rebind(mine);
  }
  /// Not a VectorXd (class comment): a copy must be asked for.
  operator const Eigen::VectorXd&() const = delete;

 private:
  [[nodiscard]] Eigen::Index grown(Eigen::Index n) const { return std::max(n, 2 * capacity()); }
  /// Points the map at the first n entries of the storage (a Map is re-pointed by constructing
  /// it anew, as Eigen::Ref re-points its own Map base).
  void rebind(Eigen::Index n) noexcept { ::new (static_cast<Base*>(this)) Base(store_.data(), n); }
  template <class Derived>
  void assign(const Eigen::DenseBase<Derived>& values) {
    const Eigen::Index n = values.size();
    if (n > capacity()) {  // evaluated into the new storage first: `values` may read the old one
      Eigen::VectorXd bigger(grown(n));
      bigger.head(n) = values;
      store_.swap(bigger);
      rebind(n);
      return;
    }
    rebind(n);
    Base::operator=(values);
  }

  Eigen::VectorXd store_;  ///< capacity() entries, the first size() of them in use
};

}  // namespace dc
