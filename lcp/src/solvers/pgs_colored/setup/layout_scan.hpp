#pragma once
// The per-contact and per-body scans at the start of pgs-colored's layout (pgs_colored_layout.hpp),
// in one run of the calling thread's team: which bodies are dynamic, whether every normal row is
// bounded by [0, ∞), and the two-point manifolds. Each part writes only its own range, and the
// manifolds' pairing is a serial pass over per-contact flags, so the result is the same bits on
// every thread count.
#include <cstdint>
#include <vector>

#include "dc/lcp/lcp_problem.hpp"

namespace dc::colored {

/// dynamic[k] = 1 when one of body k's three M⁻¹ entries is not 0 (k < bodies); partner: per
/// contact, its manifold's second contact, −2 when it is one, else −1 (may_pair below); returns
/// the first contact whose normal row has bounds other than [0, ∞), or −1. On up to `threads`
/// members of the team (serial below a few thousand contacts).
int scan_contacts(const LcpProblem& p, int bodies, int threads, std::vector<std::uint8_t>& dynamic,
                  std::vector<int>& partner);

/// Contacts c and c + 1 may form a two-point manifold ("pgs"'s pairing, pgs_matrix_free.cpp):
/// the same body_a and body_b, different features, a tangent row each exactly when the other has
/// one, rows in the order n0 (t0) n1 (t1), the same normal (bit-equal linear parts of J) and a
/// well-conditioned 2 × 2 normal block. scan_contacts pairs them greedily in contact order (c
/// pairs unless it is the second point of the pair before).
bool may_pair(const LcpProblem& p, int c);

}  // namespace dc::colored
