// The deepcontact commands across MPI ranks (docs/cluster.md): the ranks' blocks, and
// `generate` under `mpirun -n 2` (each rank writing its own shards) gives the one-process data set.
// The CLI case needs the build's MPI launcher (DC_TEST_MPIRUN) and is compiled out without
// it. bench (its report's plots cost a minute under load), train and the kill/resume cases
// are in scripts/check-mpi.sh (CI).
#include <gtest/gtest.h>

#include <cstdlib>
#include <string>

#include "cli_helpers.hpp"
#include "cluster/comm.hpp"
#include "dc/core/error.hpp"
#include "dc/io/h5.hpp"
#include "h5_compare.hpp"

namespace dc {
namespace {

using test::TempDir;

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
