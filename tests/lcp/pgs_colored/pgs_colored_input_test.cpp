// pgs-colored's input checks on threads (pgs_colored_input.hpp) against the serial ones
// (solver_common.hpp's check_input = LcpProblem::validate + the initial guess): the same
// verdict and the same message for valid problems and for each kind of broken input, on 1, 2
// and 3 threads; a valid λ⁰ is used in place (no copy), an empty one becomes zeros. A problem
// stamped by its builder (StructureStamp) has only its values checked, with the same messages;
// a copy or a resized one is checked whole.
#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <algorithm>
#include <limits>
#include <span>
#include <string>
#include <vector>

#include "lcp/solver_test_problems.hpp"
#include "solvers/pgs_colored/pgs_colored_input.hpp"
#include "solvers/solver_common.hpp"

namespace dc {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

/// p's contacts rebuilt with `edit` applied to each (rows named as edited).
void edit_contacts(LcpProblem& p, const std::function<void(int, ContactConstraint&)>& edit) {
  ContactConstraints out;
  for (int c = 0; c < p.constraints.size(); ++c) {
    ContactConstraint k = p.constraints[c];
    edit(c, k);
    out.add(k);
  }
  p.constraints = out;
}

/// The first contact with friction loses its tangent row (μ = 0, no tangent row) while the
/// contacts keep claiming p.rows() rows (ContactConstraints::overwrite); returns that row, still
/// coupled to the contact's normal row.
int drop_tangent(LcpProblem& p) {
  std::vector<ContactConstraint> ks(p.constraints.contacts().begin(), p.constraints.contacts().end());
  int c = 0;
  while (!ks[static_cast<size_t>(c)].has_friction()) ++c;
  const int t = ks[static_cast<size_t>(c)].tangent_row;
  ks[static_cast<size_t>(c)].tangent_row = -1;
  ks[static_cast<size_t>(c)].mu = 0.0;
  const std::span<ContactConstraint> out = p.constraints.overwrite(ks.size(), p.rows());
  std::copy(ks.begin(), ks.end(), out.begin());
  return t;
}

void expect_same_verdict(const LcpProblem& p, const Eigen::VectorXd& l0, const std::string& what) {
  Eigen::VectorXd copy;
  const auto serial = solvers::check_input(p, l0, "pgs-colored", copy);
  // The scratch of the row owners, kept between calls and never cleared: start it with what a
  // previous call on a valid problem would leave (each contact at its rows), the stale state
  // most likely to hide a row claimed twice.
  std::vector<int> owner(static_cast<size_t>(p.rows()), -1);
  for (int c = 0; c < p.constraints.size(); ++c)
    for (const int r : {p.constraints[c].normal_row, p.constraints[c].tangent_row})
      if (r >= 0 && r < p.rows()) owner[static_cast<size_t>(r)] = c;
  for (const int threads : {1, 2, 3}) {
    Eigen::VectorXd zeros;
    const double* start = nullptr;
    bool trusted = true;
    const auto mine = colored::check_input(p, l0, "pgs-colored", threads, zeros, start, owner, trusted);
    ASSERT_EQ(mine.has_value(), serial.has_value()) << what << ", " << threads << " threads";
    // The structural checks are skipped exactly for a stamped problem whose values pass.
    EXPECT_EQ(trusted, p.structure.holds(p) && !serial.has_value()) << what;
    if (serial) {
      EXPECT_EQ(mine->message, serial->message) << what;
      EXPECT_EQ(mine->status, serial->status) << what;
      EXPECT_TRUE(mine->lambda.isApprox(serial->lambda)) << what;
    } else {
      if (copy.size() > 0) {
        ASSERT_NE(start, nullptr) << what;
        EXPECT_EQ(Eigen::Map<const Eigen::VectorXd>(start, copy.size()), copy) << what;
      }
      if (l0.size() > 0) {
        EXPECT_EQ(start, l0.data()) << what << ": λ⁰ is used in place";
      }
    }
  }
}

TEST(PgsColoredInput, SameVerdictAndMessageAsTheSerialChecks) {
  test::TestRng rng(41);
  const LcpProblem good = test::random_contact(30, 80, true, rng, 0.5, 3);
  const int n = good.rows();
  Eigen::VectorXd l0(n);
  for (int i = 0; i < n; ++i) l0[i] = rng.uniform(0, 1);
  expect_same_verdict(good, l0, "valid");
  expect_same_verdict(good, Eigen::VectorXd(), "valid, no λ⁰");
  LcpProblem assembled = good;
  assembled.ensure_assembled_matrix();
  expect_same_verdict(assembled, l0, "valid with A");
  LcpProblem matrix_free = good;
  matrix_free.A = SparseRowMatrix();  // J only, as the engine hands it over
  expect_same_verdict(matrix_free, l0, "valid, matrix-free");
  matrix_free.b[3] = kNaN;
  expect_same_verdict(matrix_free, l0, "matrix-free, b NaN");
  // Rows not numbered in contact order (the ownership scan instead of the increasing-rows test).
  LcpProblem reordered = good;
  ASSERT_TRUE(good.constraints[3].has_friction() && good.constraints[7].has_friction());
  edit_contacts(reordered, [&](int c, ContactConstraint& k) {
    if (c == 3 || c == 7) {
      k.normal_row = good.constraints[10 - c].normal_row;
      k.tangent_row = good.constraints[10 - c].tangent_row;
    }
  });
  expect_same_verdict(reordered, l0, "valid, rows reordered");
  Eigen::VectorXd scratch;
  EXPECT_FALSE(solvers::check_input(reordered, l0, "pgs-colored", scratch).has_value()) << "reordered rows are valid";
  // A tangent row left to no contact (the count of rows kept, as overwrite() allows), still
  // coupled to its normal row: valid.
  LcpProblem unowned = good;
  drop_tangent(unowned);
  EXPECT_FALSE(solvers::check_input(unowned, l0, "pgs-colored", scratch).has_value()) << "an unowned row is valid";
  expect_same_verdict(unowned, l0, "valid, a row owned by no contact");
  expect_same_verdict(unowned, Eigen::VectorXd(), "valid, a row owned by no contact, no λ⁰");

  std::vector<std::pair<std::string, std::function<void(LcpProblem&, Eigen::VectorXd&)>>> broken = {
      {"b NaN", [](LcpProblem& p, Eigen::VectorXd&) { p.b[p.rows() - 2] = kNaN; }},
      {"λ⁰ NaN", [](LcpProblem&, Eigen::VectorXd& l) { l[5] = kNaN; }},
      {"λ⁰ size", [](LcpProblem&, Eigen::VectorXd& l) { l.conservativeResize(l.size() - 1); }},
      {"A not finite", [](LcpProblem& p, Eigen::VectorXd&) {
         p.ensure_assembled_matrix();
         p.A.valuePtr()[p.A.nonZeros() - 1] = INFINITY;
       }},
      {"negative mu", [](LcpProblem& p, Eigen::VectorXd&) {
         const int t = p.constraints[4].tangent_row >= 0 ? p.constraints[4].tangent_row : p.constraints[3].tangent_row;
         p.mu[t] = -1.0;
       }},
      {"bounds", [](LcpProblem& p, Eigen::VectorXd&) { p.lo[p.constraints[2].normal_row] = 2.0, p.hi[p.constraints[2].normal_row] = 1.0; }},
      {"lo NaN", [](LcpProblem& p, Eigen::VectorXd&) { p.lo[p.constraints[5].normal_row] = kNaN; }},
      {"hi NaN", [](LcpProblem& p, Eigen::VectorXd&) { p.hi[p.constraints[5].normal_row] = kNaN; }},
      {"lo +inf", [](LcpProblem& p, Eigen::VectorXd&) { p.lo[p.constraints[5].normal_row] = INFINITY; }},
      {"hi -inf", [](LcpProblem& p, Eigen::VectorXd&) { p.hi[p.constraints[5].normal_row] = -INFINITY; }},
      {"lo = hi = -inf", [](LcpProblem& p, Eigen::VectorXd&) {
         p.lo[p.constraints[5].normal_row] = p.hi[p.constraints[5].normal_row] = -INFINITY;
       }},
      {"λ⁰ inf", [](LcpProblem&, Eigen::VectorXd& l) { l[l.size() - 1] = -INFINITY; }},
      {"b inf", [](LcpProblem& p, Eigen::VectorXd&) { p.b[0] = INFINITY; }},
      {"mu NaN", [](LcpProblem& p, Eigen::VectorXd&) {
         int c = 0;
         while (!p.constraints[c].has_friction()) ++c;
         p.mu[p.constraints[c].tangent_row] = kNaN;
       }},
      {"mu inf", [](LcpProblem& p, Eigen::VectorXd&) {
         int c = 0;
         while (!p.constraints[c].has_friction()) ++c;
         p.mu[p.constraints[c].tangent_row] = INFINITY;
       }},
      {"coupling beyond the rows", [](LcpProblem& p, Eigen::VectorXd&) {
         int c = 0;
         while (!p.constraints[c].has_friction()) ++c;
         p.normal_row[static_cast<size_t>(p.constraints[c].tangent_row)] = p.rows() + 3;
       }},
      {"coupled to a friction row", [](LcpProblem& p, Eigen::VectorXd&) {
         int c = 0;
         while (!p.constraints[c].has_friction()) ++c;
         const int t = p.constraints[c].tangent_row;
         int d = c + 1;
         while (!p.constraints[d].has_friction()) ++d;
         p.normal_row[static_cast<size_t>(p.constraints[d].tangent_row)] = t;
       }},
      {"dt", [](LcpProblem& p, Eigen::VectorXd&) { p.dt = 0.0; }},
      {"body beyond J", [](LcpProblem& p, Eigen::VectorXd&) {
         edit_contacts(p, [&](int c, ContactConstraint& k) {
           if (c == 9) k.body_b = static_cast<int>(p.J.cols() / 3) + 1;
         });
       }},
      {"row claimed twice", [](LcpProblem& p, Eigen::VectorXd&) {
         const int row = p.constraints[6].normal_row;
         edit_contacts(p, [&](int c, ContactConstraint& k) {
           if (c == 11) k.normal_row = row;
         });
       }},
      {"tangent not coupled", [](LcpProblem& p, Eigen::VectorXd&) {
         int c = 0;
         while (!p.constraints[c].has_friction()) ++c;
         p.mu[p.constraints[c].tangent_row] *= 2.0;
       }},
      // A row left to no contact coupled to a friction row: with contacts, the row scan leaves
      // the coupling to the contacts' pass, which covers only the rows the contacts claim.
      {"unowned row coupled to a friction row", [](LcpProblem& p, Eigen::VectorXd&) {
         const int t = drop_tangent(p);
         int d = p.constraints.size() - 1;
         while (!p.constraints[d].has_friction()) --d;
         p.normal_row[static_cast<size_t>(t)] = p.constraints[d].tangent_row;
       }},
      {"normal row is a friction row", [](LcpProblem& p, Eigen::VectorXd&) {
         int f = 0;
         while (!p.constraints[f].has_friction()) ++f;
         edit_contacts(p, [&](int c, ContactConstraint& k) {
           if (c == f) std::swap(k.normal_row, k.tangent_row);
         });
       }},
  };
  for (const auto& [what, edit] : broken) {
    LcpProblem p = good;
    Eigen::VectorXd l = l0;
    edit(p, l);
    expect_same_verdict(p, l, what);
    Eigen::VectorXd copy;
    EXPECT_TRUE(solvers::check_input(p, l, "pgs-colored", copy).has_value()) << what << " is rejected";
    // Without contacts the row checks alone decide (with them, a contact's checks see most
    // broken couplings a second time).
    LcpProblem bare = p;
    bare.constraints = ContactConstraints();
    expect_same_verdict(bare, l, what + ", no contacts");
  }
}

TEST(PgsColoredInput, AStampedProblemHasOnlyItsValuesChecked) {
  test::TestRng rng(43);
  LcpProblem good = test::random_contact(30, 80, true, rng, 0.5, 3);
  good.A = SparseRowMatrix();  // matrix-free, as the engine hands it over
  const int n = good.rows();
  Eigen::VectorXd l0(n);
  for (int i = 0; i < n; ++i) l0[i] = rng.uniform(0, 1);
  EXPECT_FALSE(good.structure.holds(good)) << "a problem built by hand is not stamped";
  LcpProblem stamped = good;
  stamped.structure.set(stamped);
  ASSERT_TRUE(stamped.structure.holds(stamped));
  expect_same_verdict(stamped, l0, "stamped");  // trusted on every thread count
  expect_same_verdict(stamped, Eigen::VectorXd(), "stamped, no λ⁰");
  // The values of the step can still fail: the full checks name them, with their message.
  std::vector<std::pair<std::string, std::function<void(LcpProblem&, Eigen::VectorXd&)>>> values = {
      {"b NaN", [](LcpProblem& p, Eigen::VectorXd&) { p.b[p.rows() - 1] = kNaN; }},
      {"b inf", [](LcpProblem& p, Eigen::VectorXd&) { p.b[0] = -INFINITY; }},
      {"λ⁰ NaN", [](LcpProblem&, Eigen::VectorXd& l) { l[7] = kNaN; }},
      {"A not finite", [](LcpProblem& p, Eigen::VectorXd&) {
         p.ensure_assembled_matrix();
         p.A.valuePtr()[0] = INFINITY;
       }},
  };
  for (const auto& [what, edit] : values) {
    LcpProblem p = good;
    Eigen::VectorXd l = l0;
    edit(p, l);
    p.structure.set(p);
    expect_same_verdict(p, l, "stamped, " + what);
    Eigen::VectorXd copy;
    EXPECT_TRUE(solvers::check_input(p, l, "pgs-colored", copy).has_value()) << what << " is rejected";
  }
  // A copy is unstamped (it may be edited), so a broken copy of a stamped problem is rejected
  // with validate()'s message.
  LcpProblem copy = stamped;
  EXPECT_FALSE(copy.structure.holds(copy));
  copy.mu[copy.constraints[0].has_friction() ? copy.constraints[0].tangent_row : copy.constraints[1].tangent_row] = -1;
  expect_same_verdict(copy, l0, "a broken copy of a stamped problem");
  LcpProblem assigned;
  assigned = stamped;
  EXPECT_FALSE(assigned.structure.holds(assigned)) << "an assigned problem is unstamped";
  // The stamp holds only for the rows and contacts it saw.
  LcpProblem grown = stamped;
  grown.structure.set(grown);
  grown.constraints.add(0, 1, 0.0);
  EXPECT_FALSE(grown.structure.holds(grown)) << "a contact added after the stamp";
  expect_same_verdict(grown, Eigen::VectorXd(), "a contact added after the stamp");
  grown.structure.set(grown);
  grown.structure.clear();
  EXPECT_FALSE(grown.structure.holds(grown));
}

}  // namespace
}  // namespace dc
