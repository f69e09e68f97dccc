// SolverId: every solver name reads to a typed id and back to the same spelling, and unknown or
// malformed names give make_solver's one-line errors (docs/lcp.md, lcp_solver.hpp).
#include <gtest/gtest.h>

#include <set>
#include <string>

#include "dc/core/error.hpp"
#include "dc/lcp/lcp_solver.hpp"
#include "dc/lcp/pgs_colored.hpp"

namespace dc {
namespace {

std::string error_of(std::string_view name) {
  try {
    (void)SolverId::parse(name);
  } catch (const ConfigError& e) {
    return e.what();
  }
  return "";
}

TEST(SolverId, EveryNameRoundTripsToADistinctKind) {
  std::set<SolverKind> kinds;
  for (const std::string& name : solver_names()) {
    const SolverId id = SolverId::parse(name);
    EXPECT_EQ(to_string(id), name);
    EXPECT_EQ(to_string(id.kind), name);
    EXPECT_EQ(id, SolverId{id.kind});  // a plain name spells no threads or kernel
    EXPECT_EQ(make_solver(id)->name(), make_solver(name)->name());
    kinds.insert(id.kind);
  }
  EXPECT_EQ(kinds.size(), solver_names().size());
}

TEST(SolverId, PgsColoredThreadsAndKernelRoundTrip) {
  const SolverId threads = SolverId::parse("pgs-colored:3");
  EXPECT_EQ(threads.kind, SolverKind::PgsColored);
  EXPECT_EQ(threads.threads, 3);
  EXPECT_FALSE(threads.kernel.has_value());
  EXPECT_EQ(to_string(threads), "pgs-colored:3");
  EXPECT_NE(threads, SolverId::parse("pgs-colored"));
  for (PgsColoredKernel k :
       {PgsColoredKernel::Auto, PgsColoredKernel::Avx512, PgsColoredKernel::Avx2, PgsColoredKernel::Scalar}) {
    const std::string name = std::string("pgs-colored:2:") + to_string(k);
    const SolverId id = SolverId::parse(name);
    EXPECT_EQ(id.threads, 2) << name;
    ASSERT_TRUE(id.kernel.has_value()) << name;
    EXPECT_EQ(*id.kernel, k) << name;
    EXPECT_EQ(to_string(id), name);
    EXPECT_EQ(SolverId::parse(to_string(id)), id);
    if (pgs_colored_kernel_available(k)) {
      EXPECT_EQ(make_solver(id)->name(), "pgs-colored");
    } else {
      EXPECT_THROW((void)make_solver(id), ConfigError) << name;
    }
  }
}

TEST(SolverId, UnknownNamesGiveOneLineErrorsListingTheValidNames) {
  const std::string unknown = error_of("gauss");
  EXPECT_EQ(unknown.find('\n'), std::string::npos);
  EXPECT_EQ(unknown.rfind("unknown LCP solver 'gauss' (valid: ", 0), 0u) << unknown;
  for (const std::string& name : solver_names()) EXPECT_NE(unknown.find(name), std::string::npos) << name;
  try {  // the string overload of make_solver parses: the same message
    (void)make_solver("gauss");
    FAIL();
  } catch (const ConfigError& e) {
    EXPECT_EQ(std::string(e.what()), unknown);
  }
  for (const char* bad : {"pgs-colored:", "pgs-colored:0", "pgs-colored:-1", "pgs-colored:x", "pgs-colored:2:",
                          "pgs-colored:2:avx3", "pgs-colored:2:avx2:1"}) {
    const std::string e = error_of(bad);
    EXPECT_EQ(e, "LCP solver '" + std::string(bad) +
                     "': expected pgs-colored:<threads>[:<kernel>], threads >= 1, kernel auto|avx512|avx2|scalar");
  }
  EXPECT_NE(error_of("PGS"), "");  // names are case-sensitive, like the scene keys
  EXPECT_NE(error_of("pgs "), "");
}

}  // namespace
}  // namespace dc
