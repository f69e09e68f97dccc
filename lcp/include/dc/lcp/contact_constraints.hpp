#pragma once
// The contact constraints of one step: for each contact, which LCP rows it owns, which two
// bodies those rows act on and how they are coupled (docs/design.md §2). Assembly builds it next to
// J and b (LcpProblem::constraints); the matrix-free PGS kernels, the warm starters, the data
// generator and the bench read rows from it instead of re-deriving them from a global
// friction switch or re-inferring contact blocks from the sparsity of J.
//
// Rows of contact c, in contact order:   normal row n_c   (λ_n ≥ 0, non-penetration)
//                                        tangent row t_c  (|λ_t| ≤ μ_c λ_n, friction) — only
//                                                          when μ_c > 0, otherwise −1
// so a scene with one μ > 0 has rows (2c, 2c+1) and a μ = 0 scene row c, but nothing may
// rely on that: μ is per contact, and a scene may mix frictionless and frictional contacts.
//
// A contact acts on body_b (≥ 0) and on body_a, or on body_b alone when body_a = −1 (a wall;
// later a static body). Several contacts may share a body pair (a polygon edge against a
// face gives two points); `feature` tells them apart, so that a contact's identity is
// (pair, feature), as in ContactKey.
//
// The per-contact view of a solution is the pair (λ_n, λ_t) with λ_t = 0 for a contact
// without a tangent row; put/lambda_n/lambda_t, scatter and gather convert between it and the
// row vector of the LCP. Interleaved per-contact arrays hold [λ_n,0, λ_t,0, λ_n,1, λ_t,1, …]
// (the layout of the data sets' lambda_star and of the SPH / CNN label channels).
#include <Eigen/Core>
#include <cstddef>
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

  [[nodiscard]] int size() const { return static_cast<int>(contacts_.size()); }
  [[nodiscard]] bool empty() const { return contacts_.empty(); }
  /// Number of LCP rows the contacts own (Σ_c 1 + [μ_c > 0]).
  [[nodiscard]] int rows() const { return rows_; }
  [[nodiscard]] const ContactConstraint& operator[](int c) const { return contacts_[static_cast<std::size_t>(c)]; }
  [[nodiscard]] std::span<const ContactConstraint> contacts() const { return contacts_; }
  [[nodiscard]] auto begin() const { return contacts_.begin(); }
  [[nodiscard]] auto end() const { return contacts_.end(); }

  // ---- per contact ⇄ rows --------------------------------------------------------------
  /// λ_n of contact c in the row vector `lambda`.
  [[nodiscard]] double lambda_n(const Eigen::VectorXd& lambda, int c) const {
    return lambda[(*this)[c].normal_row];
  }
  /// λ_t of contact c, 0 when it has no tangent row.
  [[nodiscard]] double lambda_t(const Eigen::VectorXd& lambda, int c) const {
    const int t = (*this)[c].tangent_row;
    return t >= 0 ? lambda[t] : 0.0;
  }
  /// Writes (λ_n, λ_t) of contact c into its rows (λ_t is dropped when it has no tangent row).
  void put(int c, double lambda_n, double lambda_t, Eigen::VectorXd& lambda) const {
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
