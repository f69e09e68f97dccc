#pragma once
// The builtin warm start (World::step with WarmStart::PreviousLambda) on the step's threads.
#include <vector>

#include <span>

#include "dc/engine/contact.hpp"
#include "dc/lcp/lcp_problem.hpp"
#include "world/parts/contact_lambdas.hpp"

namespace dc {

/// out ← λ⁰ for `problem`, whose contacts are `current`: each contact's (λ_n, λ_t) of the contact with
/// the same key in `previous` (0 for a new one), made feasible as project_feasible does. Both
/// lists sorted by key (InvalidArgument as match_contacts_by_key otherwise). On `threads`
/// threads by ranges of contacts, each range matched by its own merge from a binary search into
/// `previous`: the same bits as one thread (put_matched_lambda, matched_lambda.hpp). `starts` is
/// scratch (the ranges' first matches), kept by the caller with `out` so that a step allocates
/// nothing here once both have grown to the problem.
/// `previous_lambdas`: empty, or the packed (λ_n, λ_t) of every previous contact
/// (contact_lambdas.hpp), read instead of the contacts' own fields (the same numbers).
void previous_lambda(const std::vector<Contact>& previous, std::span<const ContactLambda> previous_lambdas,
                     const std::vector<Contact>& current, const LcpProblem& problem, int threads, KeptVector& out,
                     std::vector<long>& starts);

/// put_matched_lambda (matched_lambda.hpp) with previous[j]'s (λ_n, λ_t) read from
/// previous_lambdas[j] (InvalidArgument unless both have one size).
void put_matched_lambda(std::span<const Contact> previous, std::span<const ContactLambda> previous_lambdas,
                        std::span<const Contact> current, const LcpProblem& problem, KeptVector& out);

}  // namespace dc
