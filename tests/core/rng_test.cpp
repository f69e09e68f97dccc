// dc::Rng checkpoints: a restored state continues the stream exactly, and states that do
// not fit (another algorithm, size, or a damaged position) are one-line InvalidArguments.
#include <gtest/gtest.h>

#include <cstring>
#include <vector>

#include "dc/core/error.hpp"
#include "dc/core/rng.hpp"

namespace dc {
namespace {

std::vector<double> draws(Rng& rng, int n) {
  std::vector<double> v;
  for (int i = 0; i < n; ++i) {
    v.push_back(rng.uniform());
    v.push_back(rng.gaussian(2.0));
    v.push_back(static_cast<double>(rng.uniform_int(1000)));
  }
  return v;
}

TEST(Rng, RestoredStateContinuesTheStreamBitForBit) {
  Rng a(42);
  (void)draws(a, 700);  // past one 624-word block, so the saved position is mid-block
  const std::string algorithm = a.algorithm();
  const std::vector<std::uint8_t> state = a.save_state();
  const std::vector<double> expected = draws(a, 1000);

  Rng b(7);  // another seed: only the restored state decides what follows
  b.restore_state(algorithm, state);
  EXPECT_EQ(draws(b, 1000), expected);
  EXPECT_EQ(b.save_state(), a.save_state());
  EXPECT_EQ(algorithm, "mt19937");
}

TEST(Rng, StatesThatDoNotFitAreRejected) {
  Rng rng(1);
  const std::vector<std::uint8_t> state = rng.save_state();
  EXPECT_THROW(rng.restore_state("ranlux", state), InvalidArgument);
  EXPECT_THROW(rng.restore_state(rng.algorithm(), std::vector<std::uint8_t>(state.begin(), state.end() - 1)),
               InvalidArgument);
  // The position inside the 624-word block sits after the words; out of range would index
  // outside the state.
  std::vector<std::uint8_t> damaged = state;
  const int bad = 100000;
  std::memcpy(damaged.data() + 624 * sizeof(unsigned long), &bad, sizeof bad);
  try {
    rng.restore_state(rng.algorithm(), damaged);
    ADD_FAILURE() << "a damaged position was accepted";
  } catch (const InvalidArgument& e) {
    EXPECT_EQ(std::string(e.what()).find('\n'), std::string::npos);
  }
  // A rejected state leaves the stream as it was.
  Rng fresh(1);
  EXPECT_EQ(draws(rng, 10), draws(fresh, 10));
}

}  // namespace
}  // namespace dc
