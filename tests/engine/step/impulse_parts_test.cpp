// contact_impulse on threads (world/parts/impulse_parts.hpp): Δt·Jᵀλ by jobs of bodies gives
// the serial product's bits on every thread count, for J laid out as an assembled step (wall
// rows first, then pair rows sorted by body a with body b anywhere later: near a, and far for a
// few) and for J not so laid out (the product then runs serially); done() covers every column
// once, each range after its sums are final.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstring>
#include <mutex>
#include <random>
#include <utility>
#include <vector>

#include "world/parts/impulse_parts.hpp"
#include "bytes_equal.hpp"

namespace dc {
namespace {

/// A J of `n` bodies: `walls` one-body contacts (bodies spread over the pile), then for each body
/// a its pair contacts with later bodies b (mostly within `near` of a, one in 40 anywhere later);
/// two rows a contact (normal and tangent, the same columns). `shuffled`: the pair contacts in
/// random order (rows not sorted by body a).
SparseRowMatrix impulse_j(int n, int walls, int near, bool shuffled, std::mt19937& rng) {
  std::vector<std::pair<int, int>> contacts;  // (a, b); a = −1 for a wall
  std::uniform_int_distribution<int> body(0, n - 1), step(1, near), pick(0, 39);
  for (int w = 0; w < walls; ++w) contacts.emplace_back(-1, body(rng));
  const auto pairs_from = contacts.size();
  for (int a = 0; a + 1 < n; ++a)
    for (int c = 0; c < 3; ++c) {
      const int b = pick(rng) == 0 ? std::uniform_int_distribution<int>(a + 1, n - 1)(rng) : std::min(n - 1, a + step(rng));
      contacts.emplace_back(a, b);
    }
  if (shuffled) std::shuffle(contacts.begin() + static_cast<long>(pairs_from), contacts.end(), rng);
  std::uniform_real_distribution<double> value(-1.0, 1.0);
  std::vector<Eigen::Triplet<double>> t;
  int row = 0;
  for (const auto& [a, b] : contacts)
    for (int r = 0; r < 2; ++r, ++row)
      for (const int k : {a, b})
        if (k >= 0)
          for (int d = 0; d < 3; ++d) t.emplace_back(row, 3 * k + d, value(rng));
  SparseRowMatrix j(row, 3 * n);
  j.setFromTriplets(t.begin(), t.end());
  j.makeCompressed();
  return j;
}

bool equal_bits(const Eigen::VectorXd& a, const Eigen::VectorXd& b) {
  return test::bytes_equal(a, b);
}

/// Δt·Jᵀλ on `threads` threads; `covered` counts done()'s calls per column.
Eigen::VectorXd product(const SparseRowMatrix& j, const Eigen::VectorXd& lambda, int threads, std::vector<int>& covered) {
  Eigen::VectorXd impulse;
  covered.assign(static_cast<size_t>(j.cols()), 0);
  std::mutex m;
  auto done = [&](int c0, int c1) {
    const std::lock_guard<std::mutex> lock(m);
    for (int c = c0; c < c1; ++c) ++covered[static_cast<size_t>(c)];
  };
  // Always: the jobs' split even when no helper joins (a busy machine), so the split is what is tested.
  contact_impulse(j, lambda, 0.01, impulse, done, threads, ImpulseSplit::Always);
  return impulse;
}

TEST(ContactImpulse, JobsOfBodiesGiveTheSerialBitsOnEveryThreadCount) {
  std::mt19937 rng(5);
  for (const bool shuffled : {false, true})
    for (const int near : {4, 400}) {
      const int n = 6000;
      const SparseRowMatrix j = impulse_j(n, 300, near, shuffled, rng);
      Eigen::VectorXd lambda(j.rows());
      std::uniform_real_distribution<double> l(0.0, 3.0);
      for (Eigen::Index r = 0; r < lambda.size(); ++r) lambda[r] = l(rng);
      std::vector<int> covered;
      const Eigen::VectorXd one = product(j, lambda, 1, covered);
      ASSERT_TRUE(equal_bits(one, Eigen::VectorXd(j.transpose() * lambda * 0.01)));  // Eigen's sums
      for (const int threads : {2, 3, 8}) {
        EXPECT_TRUE(equal_bits(one, product(j, lambda, threads, covered)))
            << threads << " threads, near " << near << (shuffled ? ", shuffled" : "");
        EXPECT_TRUE(std::all_of(covered.begin(), covered.end(), [](int c) { return c == 1; })) << threads << " threads";
      }
    }
}

}  // namespace
}  // namespace dc
