#pragma once
// Private to "pgs-colored" (dc/lcp/pgs_colored.hpp): the colouring in contact order, the
// default (PgsColoredDef::ordered_colors). A colour-ordered sweep is a Gauss–Seidel sweep in
// another row order; which order decides how far a sweep carries a load through a pile. This
// rule keeps "pgs"'s order: a contact takes the colour after the last colour of its dynamic
// bodies' earlier contacts (in contact order), so every two contacts sharing a body are swept in
// contact order, and the sweep is "pgs"'s sweep, iterate for iterate, while the chains of
// contacts fit in kMaxColors colours. A longer chain wraps round: the contact takes the first
// colour free on its bodies from (last + 1) mod kMaxColors on, and the overflow set when none is.
// The greedy rule (contact_coloring.hpp: the lowest free colour) needs fewer colours but sweeps
// a stack's contacts in red–black order, which leaves more penetration per sweep on resting
// stacks (docs/lcp.md "Colour order"). The second contact of a two-point manifold
// (partner = −2) takes its first contact's colour: both are one lane.
#include <cstdint>
#include <span>
#include <vector>

#include "dc/lcp/contact_constraints.hpp"
#include "solvers/pgs_colored/coloring/contact_coloring.hpp"

namespace dc::colored {

class OrderedColorer {
 public:
  /// Colours `contacts` (dynamic[k]: body k conflicts; partner as Prepared::partner). A call
  /// whose colours equal the last call's returns repeated = true and the same generation.
  /// Throws InvalidArgument when a contact names a body outside `dynamic`.
  const ContactColoring& color(const ContactConstraints& contacts, std::span<const std::uint8_t> dynamic,
                               const std::vector<int>& partner);

 private:
  ContactColoring out_;
  std::vector<int> next_;            // this call's colours before they replace out_.color
  std::vector<std::uint64_t> used_;  // per body: bit c set when colour c holds one of its contacts
  std::vector<std::int8_t> last_;    // per body: the colour of its latest contact, −1 none
};

}  // namespace dc::colored
