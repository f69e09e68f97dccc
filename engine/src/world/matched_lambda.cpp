#include "dc/engine/matched_lambda.hpp"

#include <string>

#include "dc/core/error.hpp"
#include "dc/engine/contact_match.hpp"
#include "world/parts/warm_start_parts.hpp"

namespace dc {

namespace {

/// put_matched_lambda into `out`, zeroed and of the problem's rows; lambda_of(p) is the
/// (λ_n, λ_t) of the previous contact p (its own fields, or its packed ContactLambda).
template <class LambdaOf>
void put_matched_zeroed(std::span<const Contact> previous, std::span<const Contact> current, const LcpProblem& problem,
                        Eigen::Ref<Eigen::VectorXd> out, const LambdaOf& lambda_of) {
  // Separate passes: the merge's branches follow the keys, the projection's rows stream without
  // them (one loop doing both runs slower on large piles).
  for_each_matched_contact(previous, current, [&](std::size_t c, const Contact& p) {
    const ContactLambda l = lambda_of(p);
    problem.constraints.put(static_cast<int>(c), l.n, l.t, out);
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

/// A previous contact's own (λ_n, λ_t).
ContactLambda own_lambda(const Contact& p) { return ContactLambda{p.lambda_n, p.lambda_t}; }

}  // namespace

void put_matched_lambda(std::span<const Contact> previous, std::span<const Contact> current, const LcpProblem& problem,
                        Eigen::VectorXd& out) {
  out.setZero(problem.rows());
  put_matched_zeroed(previous, current, problem, out, own_lambda);
}

void put_matched_lambda(std::span<const Contact> previous, std::span<const Contact> current, const LcpProblem& problem,
                        KeptVector& out) {
  out.setZero(problem.rows());
  put_matched_zeroed(previous, current, problem, out, own_lambda);
}

void put_matched_lambda(std::span<const Contact> previous, std::span<const ContactLambda> previous_lambdas,
                        std::span<const Contact> current, const LcpProblem& problem, KeptVector& out) {
  if (previous_lambdas.size() != previous.size())
    throw InvalidArgument("put_matched_lambda: " + std::to_string(previous_lambdas.size()) + " packed λ for " +
                          std::to_string(previous.size()) + " previous contacts");
  out.setZero(problem.rows());
  const Contact* const first = previous.data();
  put_matched_zeroed(previous, current, problem, out,
                     [&](const Contact& p) { return previous_lambdas[static_cast<std::size_t>(&p - first)]; });
}

}  // namespace dc
