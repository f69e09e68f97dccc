#pragma once
// Narrow phase: analytic circle–circle and circle–wall contacts (docs/design.md §1: analytic
// tests for circles). A contact is created when the gap g is below the pair's
// speculative distance s_a + s_b, with s_k = margin/2 + |v_k| Δt (walls have s = 0, and
// the circle then gets the whole margin): a row whose gap is still open only stops the
// bodies from closing more than g within the step (b_n += g/Δt), so fast bodies cannot
// tunnel, while slow distant pairs create no rows at all.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <optional>
#include <utility>
#include <vector>

#include "dc/engine/body_state.hpp"
#include "dc/engine/contact.hpp"
#include "dc/engine/circle_probe.hpp"
#include "dc/engine/world_def.hpp"

namespace dc {

/// Speculative reach s_k of body k [m] (inline: collide() computes it for every body).
inline double speculative_reach(const BodyState& s, int k, const ContactSection& c, double dt) {
  return 0.5 * c.margin + length(s.velocity[static_cast<size_t>(k)]) * dt;
}

/// Contact between circles a and b when their gap is below `threshold` [m].
/// Coincident centres (distance < 1e-12·(r_a + r_b)) use the normal (0, 1), so that the
/// outcome is deterministic and finite; the overlap is then r_a + r_b.
std::optional<Contact> circle_circle(const BodyState& s, int a, int b, double threshold);
/// circle_circle(s, a, b, s_a + s_b) from the packed records `pa`, `pb` of bodies a and b: the
/// same contact, bit for bit.
std::optional<Contact> circle_circle(const CircleProbe& pa, const CircleProbe& pb, int a, int b);

/// Unit normal n of wall w (from the wall into the box) and the distance of x to the wall's
/// plane, positive inside the box [m].
inline void wall_plane(Vec2 x, Wall w, double width, double height, Vec2& n, double& dist) {
  switch (w) {
    case Wall::Left: n = {1, 0}; dist = x.x; break;
    case Wall::Right: n = {-1, 0}; dist = width - x.x; break;
    case Wall::Bottom: n = {0, 1}; dist = x.y; break;
    case Wall::Top: n = {0, -1}; dist = height - x.y; break;
  }
}

/// The circle pair test on the fields of bodies a and b: writes the contact into `c` and returns
/// true when the gap is below `threshold` [m] (circle_circle's formula; the appenders below and
/// the entry points share it, so every path gives the same bits).
inline bool circle_pair(Vec2 xa, double ra, Vec2 xb, double rb, int a, int b, double threshold, Contact& c) {
  const Vec2 d = xb - xa;
  const double rsum = ra + rb;
  const double dist2 = length_squared(d);
  const double reach = rsum + threshold;  // cheap reject before the square root
  if (dist2 >= reach * reach) return false;
  const double dist = std::sqrt(dist2);
  c.key = ContactKey::pair(a, b);
  c.body_a = a;
  c.body_b = b;
  c.normal = dist > 1e-12 * rsum ? (1.0 / dist) * d : Vec2{0.0, 1.0};
  c.gap = dist - rsum;
  c.point = xa + (ra + 0.5 * c.gap) * c.normal;  // midway between the two surfaces along the normal
  return true;
}

/// circle_circle(pa, pb, a, b) appended to `out` when it exists, built in place.
inline void add_circle_circle(const CircleProbe& pa, const CircleProbe& pb, int a, int b, std::vector<Contact>& out) {
  const Vec2 d = pb.centre - pa.centre;
  const double reach = (pa.radius + pb.radius) + (pa.spec + pb.spec);
  if (length_squared(d) >= reach * reach) return;  // the reject of circle_pair, before any write
  circle_pair(pa.centre, pa.radius, pb.centre, pb.radius, a, b, pa.spec + pb.spec, out.emplace_back());
}

/// Calls emit(a, b) for each candidate pair (a, b) of pairs[q0, q1) (sorted by body a) that
/// passes add_circle_circle's reach test, in pair order. By blocks of pairs: first which pairs
/// pass (the outcome written, not branched on: it follows no pattern a branch predictor learns),
/// then emit on those, their records still in cache. Body b's record is fetched kAhead pairs
/// early (a hint).
template <class Emit>
inline void for_pair_contacts(const CircleProbe* probes, const std::pair<int, int>* pairs, long q0, long q1, Emit&& emit) {
  constexpr long kBlock = 256, kAhead = 8;
  int pass[kBlock];
  for (long b0 = q0; b0 < q1; b0 += kBlock) {
    const long b1 = std::min(q1, b0 + kBlock);
    int m = 0;
    for (long q = b0; q < b1; ++q) {
      if (q + kAhead < q1) __builtin_prefetch(&probes[pairs[q + kAhead].second]);
      const CircleProbe& pa = probes[pairs[q].first];
      const CircleProbe& pb = probes[pairs[q].second];
      const Vec2 d = pb.centre - pa.centre;
      const double reach = (pa.radius + pb.radius) + (pa.spec + pb.spec);
      pass[m] = static_cast<int>(q - b0);
      m += static_cast<int>(!(length_squared(d) >= reach * reach));  // add_circle_circle's reject, negated
    }
    for (int h = 0; h < m; ++h) emit(pairs[b0 + pass[h]].first, pairs[b0 + pass[h]].second);
  }
}

/// add_circle_circle(probes[a], probes[b], a, b, out) for each candidate pair (a, b) of
/// pairs[q0, q1) (for_pair_contacts), adding |b − a| to `spread_sum` and 1 to `spread_pairs` per
/// contact added.
inline void add_pair_contacts(const CircleProbe* probes, const std::pair<int, int>* pairs, long q0, long q1,
                              std::vector<Contact>& out, std::int64_t& spread_sum, std::int64_t& spread_pairs) {
  for_pair_contacts(probes, pairs, q0, q1, [&](int a, int b) {
    add_circle_circle(probes[a], probes[b], a, b, out);
    spread_sum += std::abs(b - a);
    ++spread_pairs;
  });
}

/// The number of contacts add_pair_contacts(probes, pairs, q0, q1, …) adds (its reach test
/// alone: no contact is built).
inline long count_pair_contacts(const CircleProbe* probes, const std::pair<int, int>* pairs, long q0, long q1) {
  long count = 0;
  for (long q = q0; q < q1; ++q) {
    const CircleProbe& pa = probes[pairs[q].first];
    const CircleProbe& pb = probes[pairs[q].second];
    const Vec2 d = pb.centre - pa.centre;
    const double reach = (pa.radius + pb.radius) + (pa.spec + pb.spec);
    count += static_cast<long>(!(length_squared(d) >= reach * reach));
  }
  return count;
}

/// add_pair_contacts' contacts written to out[0, count_pair_contacts(…)) in place of appended
/// (each element reset to Contact{} first, as emplace_back() builds it: the same bits).
inline void write_pair_contacts(const CircleProbe* probes, const std::pair<int, int>* pairs, long q0, long q1,
                                Contact* out, std::int64_t& spread_sum, std::int64_t& spread_pairs) {
  for_pair_contacts(probes, pairs, q0, q1, [&](int a, int b) {
    const CircleProbe &pa = probes[a], &pb = probes[b];
    Contact& c = *out++;
    c = Contact{};
    circle_pair(pa.centre, pa.radius, pb.centre, pb.radius, a, b, pa.spec + pb.spec, c);
    spread_sum += std::abs(b - a);
    ++spread_pairs;
  });
}

/// Contact between circle k and wall `w` of a box of the given size, when the gap is
/// below `threshold` [m]. Normals point from the wall into the box.
std::optional<Contact> circle_wall(const BodyState& s, int k, Wall w, double width, double height,
                                   double threshold);

/// The contact of circle k (centre x, radius r) with wall w at the given gap [m] (circle_wall).
inline void fill_circle_wall(Vec2 x, double r, int k, Wall w, Vec2 n, double gap, Contact& c) {
  c.key = ContactKey::wall(w, k);
  c.body_a = static_cast<int>(w);
  c.body_b = k;
  c.normal = n;
  c.gap = gap;
  c.point = x - (r + 0.5 * gap) * n;
}

/// circle_wall of circle k (centre x, radius r) appended to `out` when it exists, built in place.
inline void add_circle_wall(Vec2 x, double r, int k, Wall w, double width, double height, double threshold,
                            std::vector<Contact>& out) {
  Vec2 n;
  double dist = 0;  // centre distance to the wall plane, positive inside the box
  wall_plane(x, w, width, height, n, dist);
  const double gap = dist - r;
  if (gap < threshold) fill_circle_wall(x, r, k, w, n, gap, out.emplace_back());
}

/// add_circle_wall(centre, radius, k, W, width, height, 2·spec) for each circle k of [k0, k1)
/// with the packed record probes[k], in body order (the wall's plane chosen once per call).
template <Wall W>
inline void add_wall_contacts_of(const CircleProbe* probes, int k0, int k1, double width, double height,
                                 std::vector<Contact>& out) {
  for (int k = k0; k < k1; ++k) {
    const CircleProbe& p = probes[k];
    Vec2 n;
    double dist = 0;
    wall_plane(p.centre, W, width, height, n, dist);
    const double gap = dist - p.radius;
    if (gap < 2 * p.spec) fill_circle_wall(p.centre, p.radius, k, W, n, gap, out.emplace_back());
  }
}

/// add_wall_contacts_of<w>.
inline void add_wall_contacts(const CircleProbe* probes, int k0, int k1, Wall w, double width, double height,
                              std::vector<Contact>& out) {
  switch (w) {
    case Wall::Left: add_wall_contacts_of<Wall::Left>(probes, k0, k1, width, height, out); break;
    case Wall::Right: add_wall_contacts_of<Wall::Right>(probes, k0, k1, width, height, out); break;
    case Wall::Bottom: add_wall_contacts_of<Wall::Bottom>(probes, k0, k1, width, height, out); break;
    case Wall::Top: add_wall_contacts_of<Wall::Top>(probes, k0, k1, width, height, out); break;
  }
}

/// Signed gap [m] of contact c's pair (two circles, or a circle and the wall c.body_a of the
/// width × height box) at the positions of `s`, computed as circle_circle / circle_wall do.
/// Measures what a step did to this step's contacts (StepOutcome). A contact with a
/// non-circle (shape table present) is re-measured from its witness anchors instead.
double contact_gap(const BodyState& s, const Contact& c, double width, double height);

}  // namespace dc
