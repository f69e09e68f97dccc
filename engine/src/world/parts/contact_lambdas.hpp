#pragma once
// The solved (λ_n, λ_t) of a contact list packed apart from its contacts: integrate() gathers
// them from the solved rows into 16 bytes a contact and the next step's builtin warm start reads
// them there: two doubles written into every 128-byte Contact would cost a read for ownership
// of a cache line per contact, and the warm start would read that line back. The
// contacts' own lambda_n, lambda_t are written from the packed values when a caller reads the
// list (World::contacts(), previous_contacts(): the same numbers, later).
#include <Eigen/Core>
#include <span>
#include <vector>

#include "dc/engine/contact.hpp"
#include "dc/lcp/lcp_problem.hpp"

namespace dc {

/// out[c] ← (cons.lambda_n(λ, c), cons.lambda_t(λ, c)) for every contact c of `cons` (out
/// resized to cons.size(); its storage reused).
void gather_contact_lambdas(const ContactConstraints& cons, const Eigen::Ref<const Eigen::VectorXd>& lambda,
                            std::vector<ContactLambda>& out);

/// contacts[c].lambda_n, lambda_t ← lambdas[c] (both of one size).
void store_contact_lambdas(std::span<const ContactLambda> lambdas, std::span<Contact> contacts);

}  // namespace dc
