#include "dc/engine/matched_lambda.hpp"

#include "dc/engine/contact_match.hpp"

namespace dc {

namespace {

/// put_matched_lambda into `out`, zeroed and of the problem's rows.
void put_matched_zeroed(std::span<const Contact> previous, std::span<const Contact> current, const LcpProblem& problem,
                        Eigen::Ref<Eigen::VectorXd> out) {
  // Separate passes: the merge's branches follow the keys, the projection's rows stream without
  // them (one loop doing both runs slower on large piles).
  for_each_matched_contact(previous, current, [&](std::size_t c, const Contact& p) {
    problem.constraints.put(static_cast<int>(c), p.lambda_n, p.lambda_t, out);
  });
  // The projection contact by contact when the constraints own the rows (an assembled
  // problem): each contact's normal row, then its tangent row, whose bounds read only that
  // normal row, so the numbers are project_feasible's (which clamps all normal rows first); one
  // pass over the contacts instead of two over the rows with a normal_row lookup per row.
  const ContactConstraints& k = problem.constraints;
  if (k.size() == static_cast<int>(current.size()) && k.rows() == problem.rows()) {
    bool owned = true;
    for (int c = 0; c < static_cast<int>(current.size()); ++c) owned &= project_contact_rows(problem, c, out);
    if (owned) return;
  }
  project_feasible(problem, out);  // idempotent on rows already projected
}

}  // namespace

void put_matched_lambda(std::span<const Contact> previous, std::span<const Contact> current, const LcpProblem& problem,
                        Eigen::VectorXd& out) {
  out.setZero(problem.rows());
  put_matched_zeroed(previous, current, problem, out);
}

void put_matched_lambda(std::span<const Contact> previous, std::span<const Contact> current, const LcpProblem& problem,
                        KeptVector& out) {
  out.setZero(problem.rows());
  put_matched_zeroed(previous, current, problem, out);
}

}  // namespace dc
