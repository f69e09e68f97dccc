// ContactColorer's reuse path against a plain reference of its rule (contact_coloring.hpp):
// a contact keeps the colour of the first contact of the previous call with its identity
// (lower body, other body, feature) whose colour is still free on its bodies, contacts taken
// in order; then the others take the lowest free colour, in order. The reference keeps the
// previous call in a std::map and marks colours in per-body sets, so it shares no code (and
// no pass structure) with the colourer. Checked on contact sets that persist, lose and gain
// contacts, come out of body order, share keys (two walls of one body) and have static bodies.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstring>
#include <map>
#include <set>
#include <string>
#include <tuple>
#include <vector>

#include "dc/core/error.hpp"
#include "lcp/solver_test_problems.hpp"
#include "solvers/pgs_colored/coloring/contact_coloring.hpp"

namespace dc {
namespace {

using Key = std::tuple<int, int, int>;  // (lower body, other body or −1, feature)

Key key_of(const ContactConstraint& k) {
  if (k.has_body_a()) return {std::min(k.body_a, k.body_b), std::max(k.body_a, k.body_b), k.feature};
  return {k.body_b, -1, k.feature};
}

/// The contacts in the order the rule visits them, for `chunk` contacts per chunk (0: one chunk):
/// the interior contacts (every dynamic body private to their chunk: in the chunk's body range
/// and touched by no contact of another chunk) in contact order, then the others. Written from
/// the header's definition with sets, no shared code.
std::vector<int> visiting_order(const ContactConstraints& cons, const std::vector<std::uint8_t>& dyn, int chunk) {
  const int nc = cons.size(), nb = static_cast<int>(dyn.size());
  const int chunks = chunk > 0 ? std::max(1, nc / chunk) : 1;
  std::vector<int> first_contact(static_cast<size_t>(chunks) + 1);
  for (int q = 0; q <= chunks; ++q) first_contact[static_cast<size_t>(q)] = static_cast<int>(static_cast<long long>(q) * nc / chunks);
  auto chunk_of = [&](int c) {
    return static_cast<int>(std::upper_bound(first_contact.begin(), first_contact.end(), c) - first_contact.begin()) - 1;
  };
  std::vector<int> range(static_cast<size_t>(chunks) + 1, 0);  // chunk q owns [range[q], range[q+1])
  for (int q = 1; q < chunks; ++q)
    range[static_cast<size_t>(q)] =
        std::min(nb, std::max(range[static_cast<size_t>(q) - 1], std::get<0>(key_of(cons[first_contact[static_cast<size_t>(q)]]))));
  range[static_cast<size_t>(chunks)] = nb;
  std::vector<std::set<int>> touched(dyn.size());
  for (int c = 0; c < nc; ++c)
    for (int body : {cons[c].body_a, cons[c].body_b})
      if (body >= 0 && dyn[static_cast<size_t>(body)]) touched[static_cast<size_t>(body)].insert(chunk_of(c));
  std::vector<int> interior, boundary;
  for (int c = 0; c < nc; ++c) {
    const int q = chunk_of(c);
    bool inside = true;
    for (int body : {cons[c].body_a, cons[c].body_b})
      if (body >= 0 && dyn[static_cast<size_t>(body)])
        inside &= touched[static_cast<size_t>(body)] == std::set<int>{q} && body >= range[static_cast<size_t>(q)] &&
                  body < range[static_cast<size_t>(q) + 1];
    (inside ? interior : boundary).push_back(c);
  }
  interior.insert(interior.end(), boundary.begin(), boundary.end());
  return interior;
}

/// The colouring rule, written for clarity.
class ReferenceColorer {
 public:
  explicit ReferenceColorer(int chunk = 0) : chunk_(chunk) {}
  std::vector<int> color(const ContactConstraints& cons, const std::vector<std::uint8_t>& dyn) {
    const int nc = cons.size();
    const std::vector<int> order = visiting_order(cons, dyn, chunk_);
    std::vector<int> out(static_cast<size_t>(nc), ContactColoring::kOverflow);
    std::vector<std::set<int>> used(dyn.size());
    auto bodies = [&](const ContactConstraint& k) {
      std::vector<int> b;
      for (int body : {k.body_a, k.body_b})
        if (body >= 0 && dyn[static_cast<size_t>(body)]) b.push_back(body);
      return b;
    };
    auto is_free = [&](const ContactConstraint& k, int colour) {
      for (int body : bodies(k))
        if (used[static_cast<size_t>(body)].count(colour)) return false;
      return true;
    };
    auto take = [&](int c, int colour) {
      out[static_cast<size_t>(c)] = colour;
      for (int body : bodies(cons[c])) used[static_cast<size_t>(body)].insert(colour);
    };
    std::vector<bool> done(static_cast<size_t>(nc), false);
    for (const int c : order) {
      const auto it = prev_.find(key_of(cons[c]));
      if (it == prev_.end()) continue;
      for (int colour : it->second) {
        if (colour == ContactColoring::kOverflow || !is_free(cons[c], colour)) continue;
        take(c, colour);
        done[static_cast<size_t>(c)] = true;
        break;
      }
    }
    for (const int c : order) {
      if (done[static_cast<size_t>(c)]) continue;
      for (int colour = 0; colour < ContactColoring::kMaxColors; ++colour) {
        if (is_free(cons[c], colour)) {
          take(c, colour);
          break;
        }
      }
    }
    prev_.clear();
    for (int c = 0; c < nc; ++c) prev_[key_of(cons[c])].push_back(out[static_cast<size_t>(c)]);
    return out;
  }

 private:
  int chunk_;
  std::map<Key, std::vector<int>> prev_;  // per identity: colours in contact order
};

/// A random contact set on `bodies` bodies: pairs, walls (several per body: shared keys) and
/// repeated pairs with other features.
ContactConstraints random_set(int bodies, int contacts, test::TestRng& rng) {
  ContactConstraints k;
  for (int c = 0; c < contacts; ++c) {
    const int b = rng.below(bodies);
    if (rng.below(5) == 0) {
      k.add(-1, b, 0.5, rng.below(2));
    } else {
      int a = rng.below(bodies);
      if (a == b) a = (a + 1) % bodies;
      k.add(a, b, rng.below(3) == 0 ? 0.0 : 0.5, rng.below(2));
    }
  }
  return k;
}

/// `from` with about `drop` of its contacts removed, `add` new random ones inserted at random
/// places, and (shuffle) a few neighbours swapped.
ContactConstraints perturb(const ContactConstraints& from, int bodies, double drop, int add, bool shuffle,
                           test::TestRng& rng) {
  std::vector<ContactConstraint> v;
  for (const ContactConstraint& k : from)
    if (rng.uniform() >= drop) v.push_back(k);
  const ContactConstraints extra = random_set(bodies, add, rng);
  for (const ContactConstraint& k : extra)
    v.insert(v.begin() + (v.empty() ? 0 : rng.below(static_cast<int>(v.size()) + 1)), k);
  if (shuffle)
    for (size_t i = 1; i < v.size(); i += 3) std::swap(v[i - 1], v[i]);
  ContactConstraints out;
  for (const ContactConstraint& k : v) out.add(k.body_a, k.body_b, k.mu, k.feature);
  return out;
}

/// A set in ascending lower body (as the engine's broad phase gives them).
ContactConstraints sorted_by_first_body(const ContactConstraints& from) {
  std::vector<ContactConstraint> v(from.begin(), from.end());
  std::stable_sort(v.begin(), v.end(), [](const ContactConstraint& x, const ContactConstraint& y) {
    return std::get<0>(key_of(x)) < std::get<0>(key_of(y));
  });
  ContactConstraints out;
  for (const ContactConstraint& k : v) out.add(k.body_a, k.body_b, k.mu, k.feature);
  return out;
}

TEST(ContactColoringReuse, SameColoursAsTheReferenceOverChangingSets) {
  for (uint64_t seed = 1; seed <= 6; ++seed) {
    test::TestRng rng(seed);
    const int bodies = 20 + 15 * static_cast<int>(seed);
    std::vector<std::uint8_t> dyn(static_cast<size_t>(bodies), 1);
    if (seed % 2 == 0)
      for (int b = 0; b < bodies; b += 7) dyn[static_cast<size_t>(b)] = 0;  // static bodies
    ContactColorer colorer;
    ReferenceColorer reference;
    ContactConstraints cons = random_set(bodies, 3 * bodies, rng);
    ContactConstraints here;
    for (int call = 0; call < 15; ++call) {
      // Every third call repeats the last set (the repeat path where it applies); the others
      // perturb it, sorted by first body (the table's copy path) or not.
      if (call % 3 != 1) here = call % 3 == 0 ? sorted_by_first_body(cons) : cons;
      const std::vector<int> want = reference.color(here, dyn);
      const ContactColoring& got = colorer.color(here, dyn);
      ASSERT_EQ(got.color, want) << "seed " << seed << " call " << call;
      EXPECT_TRUE(is_valid_coloring(here, dyn, got));
      EXPECT_EQ(got.overflow, static_cast<int>(std::count(want.begin(), want.end(), ContactColoring::kOverflow)));
      EXPECT_EQ(got.colors, *std::max_element(want.begin(), want.end()) + 1);
      if (call == 0) {
        EXPECT_EQ(got.reused, 0);
      }
      cons = perturb(cons, bodies, 0.1, bodies / 4, call % 2 == 1, rng);
    }
  }
}

/// Repeats whose rule result is not last call's colours: two contacts with one key on static
/// bodies only (both take the first entry's colour), and an overflow (a freed colour is taken).
TEST(ContactColoringReuse, RepeatsOutsideTheShortcutFollowTheRule) {
  std::vector<std::uint8_t> dyn(70, 1);
  dyn[1] = dyn[2] = 0;
  ContactConstraints statics;
  statics.add(-1, 1, 0.5);
  statics.add(3, 4, 0.5);
  statics.add(1, 2, 0.5, 4);
  statics.add(1, 2, 0.5, 4);  // same key, no dynamic body
  statics.add(4, 5, 0.5);
  ContactConstraints star;  // 66 contacts on body 0: 64 colours and overflow
  for (int b = 1; b < 67; ++b) star.add(0, b, 0.5);
  for (const ContactConstraints* set : {&statics, &star}) {
    ContactColorer colorer;
    ReferenceColorer reference;
    for (int call = 0; call < 3; ++call) {
      const ContactColoring& got = colorer.color(*set, dyn);
      EXPECT_EQ(got.color, reference.color(*set, dyn)) << "call " << call;
      EXPECT_TRUE(is_valid_coloring(*set, dyn, got));
    }
  }
}

TEST(ContactColoringReuse, IdenticalSetKeepsEveryColour) {
  test::TestRng rng(11);
  const ContactConstraints cons = sorted_by_first_body(random_set(60, 150, rng));
  const std::vector<std::uint8_t> dyn(60, 1);
  ContactColorer colorer;
  const std::vector<int> first = colorer.color(cons, dyn).color;
  const std::uint64_t generation = colorer.last().generation;
  const ContactColoring& again = colorer.color(cons, dyn);
  EXPECT_EQ(again.color, first);
  EXPECT_TRUE(again.repeated);
  EXPECT_EQ(again.generation, generation);
  EXPECT_EQ(again.reused, cons.size());
  // One changed feature is another set: colours computed again (the same: no body changed).
  ContactConstraints changed;
  for (int c = 0; c < cons.size(); ++c)
    changed.add(cons[c].body_a, cons[c].body_b, cons[c].mu, c == 7 ? 9 : cons[c].feature);
  const ContactColoring& third = colorer.color(changed, dyn);
  EXPECT_FALSE(third.repeated);
  EXPECT_NE(third.generation, generation);
  EXPECT_EQ(third.color, first);
}

TEST(ContactColoringReuse, ABadBodyKeepsTheLastTable) {
  test::TestRng rng(5);
  const ContactConstraints cons = random_set(30, 70, rng);
  const std::vector<std::uint8_t> dyn(30, 1);
  ContactColorer colorer;
  ReferenceColorer reference;
  const std::vector<int> first = colorer.color(cons, dyn).color;
  (void)reference.color(cons, dyn);
  ContactConstraints bad = cons;
  bad.add(3, 40, 0.5);  // body 40 of 30
  EXPECT_THROW(colorer.color(bad, dyn), InvalidArgument);
  // The failed call did not replace the table: the next call reuses the first call's colours.
  const ContactConstraints next = perturb(cons, 30, 0.2, 5, false, rng);
  EXPECT_EQ(colorer.color(next, dyn).color, reference.color(next, dyn));
}

/// A set with locality, as a pile in body order gives: pairs (a, a + 1..width+1), walls on the
/// low bodies, sorted by first body, so that chunks of it have private bodies.
ContactConstraints local_set(int bodies, int width, test::TestRng& rng) {
  ContactConstraints k;
  for (int a = 0; a < bodies; ++a) {
    if (a < width && rng.below(2) == 0) k.add(-1, a, 0.5, 0);
    for (int d : {1, width, width + 1})
      if (a + d < bodies && rng.below(4) != 0) k.add(a, a + d, rng.below(3) == 0 ? 0.0 : 0.5, rng.below(2));
  }
  return sorted_by_first_body(k);
}

/// The parallel colouring (small chunks, several chunks per set) against the reference rule
/// with the same visiting order, and the same colours (memcmp) for 1, 2, 3 and 7 threads, over
/// changing sets (reuse), repeats and static bodies.
TEST(ContactColoringThreads, ChunksFollowTheRuleAndGiveTheSameColoursOnEveryThreadCount) {
  constexpr int kChunk = 120;
  for (uint64_t seed = 1; seed <= 4; ++seed) {
    test::TestRng rng(seed);
    const int bodies = 600 + 40 * static_cast<int>(seed), width = 2 + static_cast<int>(seed % 2);
    std::vector<std::uint8_t> dyn(static_cast<size_t>(bodies), 1);
    if (seed % 2 == 0)
      for (int b = 0; b < bodies; b += 9) dyn[static_cast<size_t>(b)] = 0;
    std::vector<ContactColorer> colorers;
    for (int t = 0; t < 4; ++t) colorers.emplace_back(true, kChunk);
    ReferenceColorer reference(kChunk);
    ContactConstraints cons = local_set(bodies, width, rng), here;
    for (int call = 0; call < 9; ++call) {
      // Every third call repeats the last set; the others perturb it a little (kept sorted, so
      // that most contacts persist in their chunk).
      if (call % 3 != 1) here = sorted_by_first_body(cons);
      const std::vector<int> want = reference.color(here, dyn);
      const std::string what = "seed " + std::to_string(seed) + " call " + std::to_string(call);
      const int threads[] = {1, 2, 3, 7};
      const ContactColoring& one = colorers[0].color(here, dyn, 1);
      ASSERT_EQ(one.color, want) << what;
      EXPECT_TRUE(is_valid_coloring(here, dyn, one)) << what;
      EXPECT_EQ(one.chunks, std::max(1, here.size() / kChunk)) << what;
      EXPECT_GT(one.chunks, 3) << what;
      EXPECT_GT(one.boundary, 0) << what;
      EXPECT_LT(one.boundary, here.size() / 2) << what;  // most contacts are coloured in parallel
      if (call % 3 == 1 && seed % 2 == 1) {  // (a contact between static bodies is no repeat)
        EXPECT_TRUE(one.repeated) << what;
      }
      if (call > 0 && call % 3 != 1) {
        EXPECT_GT(one.reused, here.size() / 2) << what;  // persisting contacts keep their colour
      }
      for (int t = 1; t < 4; ++t) {
        const ContactColoring& got = colorers[static_cast<size_t>(t)].color(here, dyn, threads[t]);
        ASSERT_EQ(got.color.size(), one.color.size());
        EXPECT_EQ(0, std::memcmp(got.color.data(), one.color.data(), sizeof(int) * one.color.size()))
            << what << ", " << threads[t] << " threads";
        EXPECT_EQ(got.colors, one.colors);
        EXPECT_EQ(got.reused, one.reused);
        EXPECT_EQ(got.boundary, one.boundary);
        EXPECT_EQ(got.repeated, one.repeated);
      }
      cons = perturb(cons, bodies, 0.05, bodies / 100, false, rng);
    }
  }
}

/// Below two chunks the colouring is the one-chunk greedy rule whatever the thread count, and
/// a colourer with one huge chunk gives the plain reference's colours on a chunked-size set.
TEST(ContactColoringThreads, OneChunkIsTheGreedyRule) {
  test::TestRng rng(31);
  const ContactConstraints cons = local_set(400, 10, rng);
  const std::vector<std::uint8_t> dyn(400, 1);
  ReferenceColorer greedy;
  const std::vector<int> want = greedy.color(cons, dyn);
  for (int threads : {1, 3}) {
    ContactColorer big(false, cons.size() / 2 + 1);  // nc / chunk = 1
    const ContactColoring& got = big.color(cons, dyn, threads);
    EXPECT_EQ(got.color, want);
    EXPECT_EQ(got.chunks, 1);
    EXPECT_EQ(got.boundary, 0);
  }
  // Chunked from scratch: valid, and at most one colour more than the greedy one here.
  ContactColorer chunked(false, 16);
  const ContactColoring& c = chunked.color(cons, dyn, 2);
  EXPECT_TRUE(is_valid_coloring(cons, dyn, c));
  EXPECT_LE(c.colors, *std::max_element(want.begin(), want.end()) + 2);
  // The default colourer (chunk 0) is the greedy rule on any set size and thread count.
  ContactColorer by_default(false);
  EXPECT_EQ(by_default.color(cons, dyn, 3).color, want);
  EXPECT_EQ(by_default.last().chunks, 1);
  EXPECT_THROW(ContactColorer(true, -1), InvalidArgument);
}

}  // namespace
}  // namespace dc
