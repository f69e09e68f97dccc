#include "dc/research/unrolled_pgs.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include "dc/core/error.hpp"

namespace dc {

namespace {

[[noreturn]] void bad(const std::string& msg) { throw InvalidArgument("unrolled pgs: " + msg); }

}  // namespace

// The packing mirrors pgs_matrix_free.cpp (contact_slots, pack_row): the lower body index in
// slots 0–2, the other (or nothing, for a wall) in slots 3–5; J_i accumulated per slot in the
// order of J's row; A_ii summed in slot order; J_i and b_i scaled by 1/A_ii, M⁻¹J_iᵀΔt not.
UnrolledPgs::UnrolledPgs(const LcpProblem& p) : J_(p.J), inv_mass_(p.inv_mass), dt_(p.dt) {
  const int n = p.rows();
  if (!p.has_jacobian()) bad("the problem has no Jacobian (assemble it from a world)");
  const ContactConstraints& cons = p.constraints;
  if (cons.rows() != n) bad("the problem has no contact constraints for its " + std::to_string(n) + " rows");
  const int bodies = static_cast<int>(p.J.cols() / 3) + (p.J.cols() % 3 != 0 ? 1 : 0);
  nu_ = 3 * bodies;
  if (inv_mass_.size() < p.J.cols()) bad("inv_mass has fewer entries than J has columns");
  const int zero = nu_, sink = nu_ + 3;
  std::vector<int> owner(static_cast<std::size_t>(n), -1);
  for (int c = 0; c < cons.size(); ++c) {
    owner[static_cast<std::size_t>(cons[c].normal_row)] = c;
    if (cons[c].has_friction()) owner[static_cast<std::size_t>(cons[c].tangent_row)] = c;
  }
  rows_.resize(static_cast<std::size_t>(n));
  for (int i = 0; i < n; ++i) {
    const int c = owner[static_cast<std::size_t>(i)];
    if (c < 0) bad("row " + std::to_string(i) + " belongs to no contact");
    const ContactConstraint& k = cons[c];
    const int first = k.has_body_a() ? std::min(k.body_a, k.body_b) : k.body_b;
    const int second = k.has_body_a() ? std::max(k.body_a, k.body_b) : -1;
    const int a = 3 * first, bb = second < 0 ? -1 : 3 * second;
    Row& r = rows_[static_cast<std::size_t>(i)];
    for (SparseRowMatrix::InnerIterator it(p.J, i); it; ++it) {
      const int col = static_cast<int>(it.col());
      const int off = 3 * (col / 3), comp = col % 3;
      int slot;
      if (off == a) {
        slot = comp;
      } else if (bb >= 0 && off == bb) {
        slot = 3 + comp;
      } else {
        bad("row " + std::to_string(i) + " of J acts on a body other than its contact's");
      }
      r.j[static_cast<std::size_t>(slot)] += it.value();
    }
    double diag = 0.0;
    for (int s = 0; s < 6; ++s) {
      const int off = s < 3 ? a : bb;
      if (off < 0) continue;
      const double im = p.inv_mass[off + s % 3];
      r.mj[static_cast<std::size_t>(s)] = r.j[static_cast<std::size_t>(s)] * im * p.dt;
      diag += r.j[static_cast<std::size_t>(s)] * r.mj[static_cast<std::size_t>(s)];
    }
    const double inv = 1.0 / diag;
    if (!(diag > 0 && std::isfinite(inv))) bad("row " + std::to_string(i) + " is singular (A_ii <= 0)");
    for (double& v : r.j) v *= inv;
    r.b = p.b[i] * inv;
    r.has_a = true;
    r.has_b = bb >= 0;
    r.la = a;
    r.sa = a;
    r.lb = bb < 0 ? zero : bb;
    r.sb = bb < 0 ? sink : bb;
    if (p.is_friction_row(i)) {
      r.coupled = p.normal_row[static_cast<std::size_t>(i)];
      r.mu = p.mu[i];
    } else {
      r.lo = p.lo[i];
      r.hi = p.hi[i];
      r.plain_normal = r.lo == 0.0 && r.hi == std::numeric_limits<double>::infinity();
    }
  }
}

UnrolledPgs::Piece UnrolledPgs::update(const Row& r, int i, double* lam, double* u) const {
  const double* ua = u + r.la;
  const double* ub = u + r.lb;
  const double a0 = ua[0], a1 = ua[1], a2 = ua[2], b0 = ub[0], b1 = ub[1], b2 = ub[2];
  // The engine's tree sum (pgs_matrix_free.cpp), operation for operation.
  const double s0 = std::fma(r.j[0], a0, r.j[1] * a1);
  const double s1 = std::fma(r.j[2], a2, r.j[3] * b0);
  const double s2 = std::fma(r.j[4], b1, r.j[5] * b2);
  const double res = (r.b + s0) + (s1 + s2);
  const double old = lam[i];
  const double y = old - res;
  double x;
  Piece piece;
  if (r.plain_normal) {
    if (y < 0.0) {
      x = 0.0;
      piece = Fixed;
    } else {
      x = y;
      piece = Interior;
    }
  } else if (r.coupled >= 0) {
    const double t = r.mu * std::max(0.0, lam[r.coupled]);
    if (!(t > 0.0)) {
      x = 0.0;
      piece = Fixed;
    } else if (y < -t) {
      x = -t;
      piece = Lower;
    } else if (y > t) {
      x = t;
      piece = Upper;
    } else {
      x = y;
      piece = Interior;
    }
  } else {
    x = std::min(std::max(y, r.lo), r.hi);
    piece = (y < r.lo || y > r.hi) ? Fixed : Interior;
  }
  const double d = x - old;
  lam[i] = x;
  double* sa = u + r.sa;
  double* sb = u + r.sb;
  sa[0] = std::fma(r.mj[0], d, a0);
  sa[1] = std::fma(r.mj[1], d, a1);
  sa[2] = std::fma(r.mj[2], d, a2);
  sb[0] = std::fma(r.mj[3], d, b0);
  sb[1] = std::fma(r.mj[4], d, b1);
  sb[2] = std::fma(r.mj[5], d, b2);
  return piece;
}

const Eigen::VectorXd& UnrolledPgs::forward(const Eigen::VectorXd& lambda0, int sweeps) {
  if (lambda0.size() != rows())
    bad("lambda0 has " + std::to_string(lambda0.size()) + " entries, the problem " + std::to_string(rows()) + " rows");
  if (sweeps < 0) bad("sweeps must be >= 0");
  lam_ = lambda0;
  u_.assign(static_cast<std::size_t>(nu_ + 6), 0.0);
  {
    const Eigen::VectorXd jt = J_.transpose() * lam_;  // as the engine forms Δu⁰
    for (int c = 0; c < jt.size(); ++c) u_[static_cast<std::size_t>(c)] = inv_mass_[c] * jt[c] * dt_;
  }
  sweeps_ = sweeps;
  const int n = rows();
  pieces_.resize(static_cast<std::size_t>(sweeps) * static_cast<std::size_t>(n));
  for (int s = 0; s < sweeps; ++s) {
    std::uint8_t* rec = pieces_.data() + static_cast<std::size_t>(s) * static_cast<std::size_t>(n);
    for (int i = 0; i < n; ++i) rec[i] = update(rows_[static_cast<std::size_t>(i)], i, lam_.data(), u_.data());
  }
  return lam_;
}

Eigen::VectorXd UnrolledPgs::backward(const Eigen::VectorXd& dlam_k, const Eigen::VectorXd& du_k) const {
  const int n = rows();
  if (dlam_k.size() != n) bad("backward: dlam has the wrong size");
  if (du_k.size() != 0 && du_k.size() != nu_) bad("backward: du has the wrong size");
  Eigen::VectorXd lb = dlam_k;
  std::vector<double> ub(static_cast<std::size_t>(nu_ + 6), 0.0);
  for (int c = 0; c < du_k.size(); ++c) ub[static_cast<std::size_t>(c)] = du_k[c];
  for (int s = sweeps_ - 1; s >= 0; --s) {
    const std::uint8_t* rec = pieces_.data() + static_cast<std::size_t>(s) * static_cast<std::size_t>(n);
    for (int i = n - 1; i >= 0; --i) {
      const Row& r = rows_[static_cast<std::size_t>(i)];
      double* ga = ub.data() + r.sa;
      double* gb = ub.data() + r.lb;  // only used when the row has body b (then lb = sb)
      double dbar = r.mj[0] * ga[0] + r.mj[1] * ga[1] + r.mj[2] * ga[2];
      if (r.has_b) dbar += r.mj[3] * gb[0] + r.mj[4] * gb[1] + r.mj[5] * gb[2];
      const double xbar = lb[i] + dbar;
      double ybar = 0.0;
      switch (static_cast<Piece>(rec[i])) {
        case Interior: ybar = xbar; break;
        case Fixed: break;
        case Upper: lb[r.coupled] += r.mu * xbar; break;
        case Lower: lb[r.coupled] -= r.mu * xbar; break;
      }
      lb[i] = ybar - dbar;
      // res = J_i·Δu + b: Δū −= J_iᵀ ȳ (the pass-through Δu_new = Δu_old + mj d keeps Δū).
      if (ybar != 0.0) {
        ga[0] -= r.j[0] * ybar;
        ga[1] -= r.j[1] * ybar;
        ga[2] -= r.j[2] * ybar;
        if (r.has_b) {
          gb[0] -= r.j[3] * ybar;
          gb[1] -= r.j[4] * ybar;
          gb[2] -= r.j[5] * ybar;
        }
      }
    }
  }
  // Δu⁰ = Δt M⁻¹ Jᵀ λ⁰  ⇒  λ̄⁰ += J (Δt M⁻¹ Δū⁰).
  Eigen::VectorXd g(J_.cols());
  for (int c = 0; c < g.size(); ++c) g[c] = inv_mass_[c] * dt_ * ub[static_cast<std::size_t>(c)];
  lb += J_ * g;
  return lb;
}

double UnrolledPgs::natural_map(const Row& r, int i, const double* lam, const double* u, Piece& piece) const {
  const double* ua = u + r.la;
  const double* ub = u + r.lb;
  const double res = (r.b + (r.j[0] * ua[0] + r.j[1] * ua[1] + r.j[2] * ua[2])) +
                     (r.j[3] * ub[0] + r.j[4] * ub[1] + r.j[5] * ub[2]);
  const double y = lam[i] - res;
  double p;
  if (r.coupled >= 0) {
    const double t = r.mu * std::max(0.0, lam[r.coupled]);
    if (!(t > 0.0)) {
      p = 0.0;
      piece = Fixed;
    } else if (y < -t) {
      p = -t;
      piece = Lower;
    } else if (y > t) {
      p = t;
      piece = Upper;
    } else {
      p = y;
      piece = Interior;
    }
  } else {
    p = std::min(std::max(y, r.lo), r.hi);
    piece = (y < r.lo || y > r.hi) ? Fixed : Interior;
  }
  return lam[i] - p;
}

Eigen::VectorXd UnrolledPgs::residual() const {
  Eigen::VectorXd out(rows());
  Piece piece;
  for (int i = 0; i < rows(); ++i) out[i] = natural_map(rows_[static_cast<std::size_t>(i)], i, lam_.data(), u_.data(), piece);
  return out;
}

double UnrolledPgs::residual_loss(Eigen::VectorXd& dlam, Eigen::VectorXd& du) const {
  if (dlam.size() != rows() || du.size() != nu_) bad("residual_loss: gradient buffers have the wrong size");
  double loss = 0.0;
  for (int i = 0; i < rows(); ++i) {
    const Row& r = rows_[static_cast<std::size_t>(i)];
    Piece piece;
    const double ri = natural_map(r, i, lam_.data(), u_.data(), piece);
    loss += ri * ri;
    const double rbar = 2.0 * ri;
    dlam[i] += rbar;  // r = λ_i − p
    const double pbar = -rbar;
    switch (piece) {
      case Interior: {
        dlam[i] += pbar;  // p = y = λ_i − (J_i·Δu + b_i)
        for (int s = 0; s < 3; ++s) du[r.la + s] -= r.j[static_cast<std::size_t>(s)] * pbar;
        if (r.has_b)
          for (int s = 0; s < 3; ++s) du[r.lb + s] -= r.j[static_cast<std::size_t>(3 + s)] * pbar;
        break;
      }
      case Fixed: break;
      case Upper: dlam[r.coupled] += r.mu * pbar; break;
      case Lower: dlam[r.coupled] -= r.mu * pbar; break;
    }
  }
  return loss;
}

double UnrolledPgs::distance_loss(const Eigen::VectorXd& target, Eigen::VectorXd& dlam) const {
  if (target.size() != rows() || dlam.size() != rows()) bad("distance_loss: sizes differ from the problem's rows");
  const Eigen::VectorXd e = lam_ - target;
  double loss = 0.0;
  for (int i = 0; i < rows(); ++i) loss += e[i] * e[i];
  dlam += 2.0 * e;
  return loss;
}

}  // namespace dc
