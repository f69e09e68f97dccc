#include "dc/engine/matched_lambda.hpp"

#include "dc/engine/contact_match.hpp"

namespace dc {

void put_matched_lambda(std::span<const Contact> previous, std::span<const Contact> current, const LcpProblem& problem,
                        Eigen::VectorXd& out) {
  // Separate passes: the merge's branches follow the keys, the projection's rows stream without
  // them (one loop doing both runs slower on large piles).
  out.setZero(problem.rows());
  for_each_matched_contact(previous, current, [&](std::size_t c, const Contact& p) {
    problem.constraints.put(static_cast<int>(c), p.lambda_n, p.lambda_t, out);
  });
  project_feasible(problem, out);
}

}  // namespace dc
