// pgs-colored's locality numbering of the bodies and the key order of the contacts
// (body_numbering.hpp).
#include "solvers/pgs_colored/setup/body_numbering.hpp"

#include <algorithm>

#include "dc/core/work_team.hpp"

namespace dc::colored {
namespace {

/// v's storage grown with headroom before it takes n entries (resize and assign alone allocate
/// exactly n, and again whenever the contact or body count exceeds its last maximum).
template <class T>
void room(std::vector<T>& v, int n) {
  const size_t want = static_cast<size_t>(n);
  if (v.capacity() < want) v.reserve(want + want / 2);
}

/// The lower and the higher body of contact k (−1: none), as the layout packs them.
inline void bodies_of(const ContactConstraint& k, int& first, int& second) {
  first = k.has_body_a() ? std::min(k.body_a, k.body_b) : k.body_b;
  second = k.has_body_a() ? std::max(k.body_a, k.body_b) : -1;
}

/// The contact graph between dynamic bodies as adjacency lists: n.head[b] … n.head[b + 1] index
/// body b's neighbours in n.next (contact order).
void adjacency(const ContactConstraints& cons, const std::vector<std::uint8_t>& dynamic, int bodies,
               BodyNumbering& n) {
  const int nc = cons.size();
  room(n.head, bodies + 2);
  n.head.assign(static_cast<size_t>(bodies) + 2, 0);
  auto joins = [&](int c, int& a, int& b) {
    bodies_of(cons[c], a, b);
    return b >= 0 && b < bodies && dynamic[static_cast<size_t>(a)] != 0 && dynamic[static_cast<size_t>(b)] != 0;
  };
  int a = 0, b = 0;
  for (int c = 0; c < nc; ++c)
    if (joins(c, a, b)) {
      ++n.head[static_cast<size_t>(a) + 2];
      ++n.head[static_cast<size_t>(b) + 2];
    }
  for (int k = 2; k < bodies + 2; ++k) n.head[static_cast<size_t>(k)] += n.head[static_cast<size_t>(k) - 1];
  room(n.next, n.head[static_cast<size_t>(bodies) + 1]);
  n.next.resize(static_cast<size_t>(n.head[static_cast<size_t>(bodies) + 1]));
  // head[k + 1] is the fill position of body k; after the fill it is body k's end = body k+1's start.
  for (int c = 0; c < nc; ++c)
    if (joins(c, a, b)) {
      n.next[static_cast<size_t>(n.head[static_cast<size_t>(a) + 1]++)] = b;
      n.next[static_cast<size_t>(n.head[static_cast<size_t>(b) + 1]++)] = a;
    }
}

/// Breadth-first from `root` over the bodies whose mark is `from`, marking them `to`; calls
/// visit(body) in visiting order; returns the last body visited.
template <class Visit>
int breadth_first(BodyNumbering& n, int root, int from, int to, Visit&& visit) {
  n.queue.clear();
  n.queue.push_back(root);
  n.mark[static_cast<size_t>(root)] = to;
  for (size_t q = 0; q < n.queue.size(); ++q) {
    const int v = n.queue[q];
    visit(v);
    for (int e = n.head[static_cast<size_t>(v)]; e < n.head[static_cast<size_t>(v) + 1]; ++e) {
      const int w = n.next[static_cast<size_t>(e)];
      if (n.mark[static_cast<size_t>(w)] != from) continue;
      n.mark[static_cast<size_t>(w)] = to;
      n.queue.push_back(w);
    }
  }
  return n.queue.back();
}

}  // namespace

void number_bodies(const ContactConstraints& cons, const std::vector<std::uint8_t>& dynamic, int bodies,
                   BodyNumbering& n) {
  adjacency(cons, dynamic, bodies, n);
  room(n.slot, bodies);
  room(n.mark, bodies);
  room(n.queue, bodies);
  n.slot.assign(static_cast<size_t>(bodies), -1);
  n.mark.assign(static_cast<size_t>(bodies), 0);
  int next = 0;
  for (int s = 0; s < bodies; ++s) {
    if (n.mark[static_cast<size_t>(s)] != 0 || n.head[static_cast<size_t>(s)] == n.head[static_cast<size_t>(s) + 1])
      continue;
    // A far end of s's piece (the last body reached from s), then the numbers from there: bands
    // across the piece, so a cut in the numbers is short.
    const int far = breadth_first(n, s, 0, 1, [](int) {});
    breadth_first(n, far, 1, 2, [&](int v) { n.slot[static_cast<size_t>(v)] = next++; });
  }
  for (int s = 0; s < bodies; ++s)
    if (n.slot[static_cast<size_t>(s)] < 0) n.slot[static_cast<size_t>(s)] = next++;
  n.bodies = bodies;
  n.age = 0;
}

double cut_share(const ContactConstraints& cons, const std::vector<std::uint8_t>& dynamic, int bodies,
                 const int* slot, BodyNumbering& n) {
  // The middle of the numbers of the bodies in contact (n.mark: 1 for those; the numbers of a
  // breadth-first numbering come first, the body indices of any order spread over all bodies).
  room(n.mark, bodies);
  n.mark.assign(static_cast<size_t>(bodies), 0);
  const int nc = cons.size();
  int a = 0, b = 0, joined = 0;
  auto number = [&](int k) { return slot != nullptr ? slot[k] : k; };
  for (int c = 0; c < nc; ++c) {
    bodies_of(cons[c], a, b);
    if (b < 0 || b >= bodies || dynamic[static_cast<size_t>(a)] == 0 || dynamic[static_cast<size_t>(b)] == 0) continue;
    n.mark[static_cast<size_t>(number(a))] = n.mark[static_cast<size_t>(number(b))] = 1;
    ++joined;
  }
  if (joined == 0) return 0.0;
  int half = 0, seen = 0, in_contact = 0;
  for (const int m : n.mark) in_contact += m;
  while (half < bodies && 2 * seen < in_contact) seen += n.mark[static_cast<size_t>(half++)];
  int cut = 0;
  for (int c = 0; c < nc; ++c) {
    bodies_of(cons[c], a, b);
    if (b < 0 || b >= bodies || dynamic[static_cast<size_t>(a)] == 0 || dynamic[static_cast<size_t>(b)] == 0) continue;
    cut += (number(a) < half) != (number(b) < half) ? 1 : 0;
  }
  return static_cast<double>(cut) / joined;
}

void order_by_key(const ContactConstraints& cons, const std::vector<std::uint8_t>& dynamic, int bodies,
                  BodyNumbering& n, int threads) {
  const int nc = cons.size();
  room(n.key, nc);
  room(n.order, nc);
  n.key.resize(static_cast<size_t>(nc));
  // A counting sort over the keys 0 … bodies in blocks of the contacts: count[part·width + k] the
  // contacts of key k in block `part`, then their first position (the blocks of a key in block
  // order: the stable order on every thread count).
  const int parts = std::max(1, std::min(threads, nc / 4096));
  const size_t width = static_cast<size_t>(bodies) + 1;
  room(n.head, static_cast<int>(width) * parts);
  n.head.assign(width * static_cast<size_t>(parts), 0);
  int* count = n.head.data();
  auto block = [&](int part, int& lo, int& hi) {
    lo = static_cast<int>(part_begin(nc, parts, part));
    hi = static_cast<int>(part_begin(nc, parts, part + 1));
  };
  WorkTeam& team = calling_thread_team();
  team.for_parts(threads, parts, [&](int part) {
    int lo = 0, hi = 0;
    block(part, lo, hi);
    int* mine = count + width * static_cast<size_t>(part);
    for (int c = lo; c < hi; ++c) {
      int a = 0, b = 0;
      bodies_of(cons[c], a, b);
      const int ka = dynamic[static_cast<size_t>(a)] != 0 ? n.slot[static_cast<size_t>(a)] : bodies;
      const int kb = b >= 0 && dynamic[static_cast<size_t>(b)] != 0 ? n.slot[static_cast<size_t>(b)] : bodies;
      const int k = std::min(ka, kb);
      n.key[static_cast<size_t>(c)] = k;
      ++mine[k];
    }
  });
  int at = 0;
  for (size_t k = 0; k < width; ++k)
    for (int part = 0; part < parts; ++part) {
      int& c = count[width * static_cast<size_t>(part) + k];
      const int here = c;
      c = at;
      at += here;
    }
  n.order.resize(static_cast<size_t>(nc));
  team.for_parts(threads, parts, [&](int part) {
    int lo = 0, hi = 0;
    block(part, lo, hi);
    int* mine = count + width * static_cast<size_t>(part);
    for (int c = lo; c < hi; ++c) n.order[static_cast<size_t>(mine[n.key[static_cast<size_t>(c)]]++)] = c;
  });
}

}  // namespace dc::colored
