#pragma once
// The contact constraints of one step: for each contact, its LCP rows, the two bodies they act
// on and their coupling (docs/design.md §2, docs/engine.md "Rows"). Assembly builds it next to J
// and b (LcpProblem::constraints); PGS kernels, warm starters, the data generator and the bench
// read rows from it, never from a global friction switch or J's sparsity.
// Rows of contact c: normal row n_c (λ_n ≥ 0) and tangent row t_c (|λ_t| ≤ μ_c λ_n) only when
// μ_c > 0, else −1. Nothing may rely on rows (2c, 2c+1) or c: μ is per contact and may be mixed.
// A contact acts on body_b (≥ 0) and body_a, or on body_b alone when body_a = −1 (a wall).
// Contacts may share a body pair; `feature` tells them apart: identity (pair, feature), as in
// ContactKey. Per contact a solution is (λ_n, λ_t), λ_t = 0 without a tangent row; interleaved
// arrays hold [λ_n,0, λ_t,0, λ_n,1, λ_t,1, …] (data sets' lambda_star, SPH / CNN label channels).
#include <Eigen/Core>
#include <cstddef>
#include <limits>
#include <span>
#include <vector>

namespace dc {

/// One contact's constraint rows and what the solver needs to know about them.
struct ContactConstraint {
  int normal_row = -1;   ///< row of the normal constraint
  int tangent_row = -1;  ///< row of the friction constraint; −1 when the contact has μ = 0
  int body_a = -1;       ///< first body, or −1 when there is none (wall)
  int body_b = -1;       ///< second body (≥ 0)
  double mu = 0.0;       ///< friction coefficient μ ≥ 0 (tangent_row ≥ 0 exactly when μ > 0)
  int feature = 0;       ///< feature id within the body pair (ContactKey::feature)

  [[nodiscard]] bool has_friction() const { return tangent_row >= 0; }
  [[nodiscard]] bool has_body_a() const { return body_a >= 0; }
};

class ContactConstraints {
 public:
  /// Appends a contact and gives it the next rows: its normal row, then its tangent row when
  /// μ > 0. Returns its index. Throws InvalidArgument for body_b < 0, body_a < −1,
  /// body_a = body_b or a μ that is negative or not finite.
  int add(int body_a, int body_b, double mu, int feature = 0);
  /// Appends a contact with the rows it names (any order, e.g. a reordered problem); the
  /// problem's validate() checks that every row is owned once. Same checks as above, and
  /// normal_row ≥ 0, tangent_row ≥ 0 exactly when μ > 0.
  int add(const ContactConstraint& contact);
  void clear();
  void reserve(std::size_t contacts);
  /// For a caller that writes the contacts itself (in parallel): sets the count to `contacts`
  /// and the row count to `rows`, and returns the contacts, every one of which the caller
  /// overwrites with rows numbered as add() numbers them and after add()'s checks (check()).
  /// The storage is reused: no element is constructed when the count does not grow.
  [[nodiscard]] std::span<ContactConstraint> overwrite(std::size_t contacts, int rows);
  /// add(body_a, body_b, mu)'s checks for contact c: throws its InvalidArgument.
  static void check(int c, int body_a, int body_b, double mu);
  /// True when add(body_a, body_b, mu) passes its checks: body_b >= 0, body_a = -1 or another
  /// body, a finite mu >= 0 (check() says which failed).
  [[nodiscard]] static bool valid(int body_a, int body_b, double mu) {
    return body_b >= 0 && body_a >= -1 && body_a != body_b && mu >= 0 && mu <= std::numeric_limits<double>::max();
  }

  [[nodiscard]] int size() const { return static_cast<int>(contacts_.size()); }
  [[nodiscard]] bool empty() const { return contacts_.empty(); }
  /// Number of LCP rows the contacts own (Σ_c 1 + [μ_c > 0]).
  [[nodiscard]] int rows() const { return rows_; }
  [[nodiscard]] const ContactConstraint& operator[](int c) const { return contacts_[static_cast<std::size_t>(c)]; }
  [[nodiscard]] std::span<const ContactConstraint> contacts() const { return contacts_; }
  [[nodiscard]] auto begin() const { return contacts_.begin(); }
  [[nodiscard]] auto end() const { return contacts_.end(); }

  // ---- per contact ⇄ rows --------------------------------------------------------------
  /// λ_n of contact c in the row vector `lambda` (any vector with operator[]: VectorXd, KeptVector, Ref).
  template <class Vector>
  [[nodiscard]] double lambda_n(const Vector& lambda, int c) const {
    return lambda[(*this)[c].normal_row];
  }
  /// λ_t of contact c, 0 when it has no tangent row.
  template <class Vector>
  [[nodiscard]] double lambda_t(const Vector& lambda, int c) const {
    const int t = (*this)[c].tangent_row;
    return t >= 0 ? lambda[t] : 0.0;
  }
  /// Writes (λ_n, λ_t) of contact c into its rows (λ_t is dropped when it has no tangent row).
  template <class Vector>
  void put(int c, double lambda_n, double lambda_t, Vector& lambda) const {
    const ContactConstraint& k = (*this)[c];
    lambda[k.normal_row] = lambda_n;
    if (k.tangent_row >= 0) lambda[k.tangent_row] = lambda_t;
  }

  /// Row vector from interleaved per-contact pairs (2 values per contact).
  /// Throws InvalidArgument when `pairs` does not hold 2·size() values.
  [[nodiscard]] Eigen::VectorXd scatter(std::span<const double> pairs) const;
  /// Row vector from separate per-contact λ_n and λ_t (λ_t may be empty when no contact has
  /// a tangent row). Throws InvalidArgument on a size mismatch.
  [[nodiscard]] Eigen::VectorXd scatter(std::span<const double> lambda_n, std::span<const double> lambda_t) const;
  /// Interleaved per-contact pairs from a row vector (λ_t = 0 for contacts without a tangent
  /// row); `pairs` is resized to 2·size(). Throws InvalidArgument when `lambda` does not have
  /// rows() entries.
  void gather(const Eigen::VectorXd& lambda, std::vector<double>& pairs) const;
  [[nodiscard]] std::vector<double> gather(const Eigen::VectorXd& lambda) const;

 private:
  std::vector<ContactConstraint> contacts_;
  int rows_ = 0;
};

}  // namespace dc
