#include "dc/engine/matched_lambda.hpp"

#include "dc/engine/contact_match.hpp"

namespace dc {
namespace {

/// The separate passes: zeros, the matched puts, project_feasible (throws what they throw).
void put_in_passes(std::span<const Contact> previous, std::span<const Contact> current, const LcpProblem& problem,
                   Eigen::VectorXd& out) {
  out.setZero(problem.rows());
  for_each_matched_contact(previous, current, [&](std::size_t c, const Contact& p) {
    problem.constraints.put(static_cast<int>(c), p.lambda_n, p.lambda_t, out);
  });
  project_feasible(problem, out);
}

}  // namespace

void put_matched_lambda(std::span<const Contact> previous, std::span<const Contact> current, const LcpProblem& problem,
                        Eigen::VectorXd& out) {
  const std::size_t nc = current.size(), np = previous.size();
  // Every row owned by one of the contacts: each is written below.
  if (problem.constraints.size() != static_cast<int>(nc) || problem.constraints.rows() != problem.rows()) {
    put_in_passes(previous, current, problem, out);
    return;
  }
  out.resize(problem.rows());
  bool ok = true;  // both lists in order and every contact's rows related as project_contact_rows needs
  std::size_t j = 0;
  for (std::size_t c = 0; c < nc && ok; ++c) {
    const ContactKey& key = current[c].key;
    if (c > 0 && key < current[c - 1].key) ok = false;
    while (j < np && previous[j].key < key) {
      if (j + 1 < np && previous[j + 1].key < previous[j].key) ok = false;
      ++j;
    }
    const bool found = j < np && previous[j].key == key;
    problem.constraints.put(static_cast<int>(c), found ? previous[j].lambda_n : 0.0, found ? previous[j].lambda_t : 0.0,
                            out);
    ok = ok && project_contact_rows(problem, static_cast<int>(c), out);
  }
  for (; ok && j + 1 < np; ++j)
    if (previous[j + 1].key < previous[j].key) ok = false;
  if (!ok) put_in_passes(previous, current, problem, out);  // its checks throw the message
}

}  // namespace dc
