// The deepcontact commands across MPI ranks (docs/cluster.md). The messages of `generate` carry
// every field of a simulation; `generate` under `mpirun -n 2` writes the one-process file.
// The CLI case needs the build's MPI launcher (DC_TEST_MPIRUN) and is compiled out without
// it. bench (its report's plots cost a minute under load), train and the kill/resume cases
// are in scripts/check-mpi.sh (CI).
#include <gtest/gtest.h>

#include <cstdlib>
#include <string>

#include "cli_helpers.hpp"
#include "cluster/comm.hpp"
#include "cluster/mpi_generate.hpp"
#include "dc/core/error.hpp"
#include "dc/io/h5.hpp"
#include "h5_compare.hpp"

namespace dc {
namespace {

using test::TempDir;

SimulationRecord distinct_record() {
  SimulationRecord r;
  r.index = 7;
  r.seed = 12345678901ULL;
  r.bodies = 3;
  r.max_residual = 2.5e-7;
  double x = 0.25;
  const auto fill_d = [&](std::vector<double>& v, std::size_t n) {
    for (std::size_t i = 0; i < n; ++i) v.push_back(x += 1.125);
  };
  const auto fill_i = [&](std::vector<std::int32_t>& v, std::size_t n) {
    for (std::size_t i = 0; i < n; ++i) v.push_back(static_cast<std::int32_t>(x += 3));
  };
  fill_i(r.step, 2);
  fill_i(r.contact_count, 2);
  fill_d(r.residual, 2);
  for (int i = 0; i < 10; ++i) r.features.push_back(static_cast<float>(x += 0.5));
  for (int i = 0; i < 4; ++i) r.labels.push_back(static_cast<float>(x += 0.5));
  fill_d(r.position, 12);
  fill_d(r.velocity, 12);
  fill_d(r.omega, 6);
  fill_d(r.angle, 6);
  fill_d(r.radius, 6);
  fill_d(r.mass, 6);
  fill_i(r.body_a, 3);
  fill_i(r.body_b, 3);
  fill_d(r.point, 6);
  fill_d(r.normal, 6);
  fill_d(r.gap, 3);
  fill_d(r.lambda_star, 6);
  return r;
}

TEST(MpiMessages, SimulationRecordRoundTripsEveryField) {
  const SimulationRecord a = distinct_record();
  const std::optional<SimulationRecord> b = cli::unpack_simulation(cli::pack_simulation(a));
  ASSERT_TRUE(b.has_value());
  EXPECT_EQ(b->index, a.index);
  EXPECT_EQ(b->seed, a.seed);
  EXPECT_EQ(b->bodies, a.bodies);
  EXPECT_EQ(b->max_residual, a.max_residual);
  EXPECT_EQ(b->step, a.step);
  EXPECT_EQ(b->contact_count, a.contact_count);
  EXPECT_EQ(b->residual, a.residual);
  EXPECT_EQ(b->features, a.features);
  EXPECT_EQ(b->labels, a.labels);
  EXPECT_EQ(b->position, a.position);
  EXPECT_EQ(b->velocity, a.velocity);
  EXPECT_EQ(b->omega, a.omega);
  EXPECT_EQ(b->angle, a.angle);
  EXPECT_EQ(b->radius, a.radius);
  EXPECT_EQ(b->mass, a.mass);
  EXPECT_EQ(b->body_a, a.body_a);
  EXPECT_EQ(b->body_b, a.body_b);
  EXPECT_EQ(b->point, a.point);
  EXPECT_EQ(b->normal, a.normal);
  EXPECT_EQ(b->gap, a.gap);
  EXPECT_EQ(b->lambda_star, a.lambda_star);
  // A cut message is an error, not a shorter record.
  cli::Bytes cut = cli::pack_simulation(a);
  cut.resize(cut.size() - 3);
  EXPECT_THROW((void)cli::unpack_simulation(cut), IoError);
}

TEST(MpiComm, BlocksCoverEveryItemOnceInOrder) {
  for (std::size_t n : {0u, 1u, 5u, 8u, 13u})
    for (int k : {1, 2, 3, 8}) {
      std::size_t next = 0;
      for (int r = 0; r < k; ++r) {
        const auto [b, e] = cli::block_of(n, r, k);
        EXPECT_EQ(b, next) << n << " " << k << " " << r;
        EXPECT_LE(e - b, n / static_cast<std::size_t>(k) + 1);
        next = e;
      }
      EXPECT_EQ(next, n);
    }
  EXPECT_FALSE(cli::world().parallel());  // a test process is not an MPI job
}

#ifdef DC_TEST_MPIRUN
int run_sh(const std::string& cmd) {
  const int s = std::system(cmd.c_str());
  return WIFEXITED(s) ? WEXITSTATUS(s) : 128;
}
std::string mpirun(int ranks) {
  return std::string(DC_TEST_MPIRUN) + " -n " + std::to_string(ranks) + " --allow-run-as-root --oversubscribe " +
         "--mca btl self,vader " + DC_CLI + " ";
}
const std::string kFamily =
    " --set world.width=12 --set world.height=12 --set bodies.mean=[6.0,6.0] --set bodies.sigma=2.0 --seed 5 "
    "--count 10..14 --steps 60 --threads 1";

TEST(MpiCli, GenerateOnTwoRanksWritesTheOneProcessFile) {
  TempDir dir;
  ASSERT_EQ(run_sh(std::string(DC_CLI) + " generate --sims 5" + kFamily + " --out " + dir / "one.h5 >/dev/null 2>&1"), 0);
  ASSERT_EQ(run_sh(mpirun(2) + "generate --sims 5" + kFamily + " --out " + dir / "two.h5 >" + dir / "log 2>&1"), 0)
      << test::slurp_file(dir / "log");
  EXPECT_NE(test::slurp_file(dir / "log").find("2 ranks x"), std::string::npos) << test::slurp_file(dir / "log");
  test::expect_same_datasets(H5File::open_read(dir / "one.h5"), H5File::open_read(dir / "two.h5"));
}

#endif

}  // namespace
}  // namespace dc
