#include "world/parts/contact_lambdas.hpp"

namespace dc {

void gather_contact_lambdas(const ContactConstraints& cons, const Eigen::Ref<const Eigen::VectorXd>& lambda,
                            std::vector<ContactLambda>& out) {
  const int nc = cons.size();
  // Half again as much room when it grows: the list and its previous-step twin are swapped every
  // step, so each must hold the contact counts of the steps it serves without reallocating.
  if (out.capacity() < static_cast<std::size_t>(nc)) out.reserve(static_cast<std::size_t>(nc) + nc / 2);
  out.resize(static_cast<std::size_t>(nc));
  ContactLambda* const o = out.data();
  for (int c = 0; c < nc; ++c) o[c] = ContactLambda{cons.lambda_n(lambda, c), cons.lambda_t(lambda, c)};
}

void store_contact_lambdas(std::span<const ContactLambda> lambdas, std::span<Contact> contacts) {
  for (std::size_t c = 0; c < contacts.size(); ++c) {
    contacts[c].lambda_n = lambdas[c].n;
    contacts[c].lambda_t = lambdas[c].t;
  }
}

}  // namespace dc
