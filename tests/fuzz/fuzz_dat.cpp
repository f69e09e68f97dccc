// libFuzzer harness: the Siconos .dat LCP reader (dc::parse_lcp_dat), and the solvers on
// whatever small problem it accepts.
//
// Properties: parsing throws only IoError; an accepted problem passes LcpProblem::validate;
// it writes back (dense and sparse-block storage, %.17g) and reads back bit-equal; the input
// without its last byte is refused or reads as the same problem (a cut never changes a value);
// for n ≤ 12 every solver returns a λ of the right size, finite, with a non-NaN residual,
// within a bounded number of sweeps (the LcpSolver contract "no solver loops forever or
// returns NaN").
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>

#include "dc/core/error.hpp"
#include "dc/lcp/dat_file.hpp"
#include "dc/lcp/lcp_solver.hpp"
#include "fuzz_common.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  dc::LcpProblem p;
  try {
    p = dc::parse_lcp_dat(text, "fuzz.dat");
  } catch (const dc::IoError&) {
    return 0;
  }
  try {
    p.validate();
  } catch (const dc::InvalidArgument&) {
    dc::fuzz::property_failed("parse_lcp_dat accepted a problem that does not validate");
  }
  try {
    const Eigen::MatrixXd A(p.A);
    for (const std::string& back : {dc::format_lcp_dat(A, Eigen::VectorXd(p.b)), dc::format_lcp_dat_blocks(p.A, Eigen::VectorXd(p.b), 2)}) {
      const dc::LcpProblem q = dc::parse_lcp_dat(back, "back.dat");
      if (Eigen::MatrixXd(q.A) != A || q.b != p.b) dc::fuzz::property_failed("a written problem does not read back bit-equal");
    }
  } catch (const std::exception&) {  // IoError or InvalidArgument
    dc::fuzz::property_failed("a writer refused, or its reader refused, a problem parse_lcp_dat accepted");
  }
  try {
    const dc::LcpProblem cut = dc::parse_lcp_dat(text.substr(0, size - 1), "cut.dat");
    if (Eigen::MatrixXd(cut.A) != Eigen::MatrixXd(p.A) || cut.b != p.b)
      dc::fuzz::property_failed("the file without its last byte reads as another problem");
  } catch (const dc::IoError&) {
  }
  if (p.rows() > 12) return 0;
  dc::SolverOptions o;
  o.max_sweeps = 60;
  o.tolerance = 1e-10;
  o.record_theta = false;
  for (const char* name : {"lemke", "newton", "pgs", "psor", "jacobi"}) {
    o.omega = std::string_view(name) == "jacobi" ? 0.5 : 1.0;
    const dc::SolveResult r = dc::make_solver(name)->solve(p, Eigen::VectorXd(), o);
    if (r.lambda.size() != p.rows()) dc::fuzz::property_failed("solver returned a wrongly sized lambda");
    if (!r.lambda.allFinite()) dc::fuzz::property_failed("solver returned a non-finite lambda");
    if (std::isnan(r.residual)) dc::fuzz::property_failed("solver returned a NaN residual");
  }
  return 0;
}
