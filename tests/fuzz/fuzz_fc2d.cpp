// libFuzzer harness: the Siconos 2D frictional-contact .dat reader (dc::parse_fc2d_dat, all
// three storages), the kind detection, and the exact and PGS solvers on whatever small
// problem it accepts.
//
// Properties: parsing and detect_dat_kind throw only IoError; an accepted problem validates
// and gives a box-friction LCP that validates; for nc ≤ 6 every solver returns a λ of the
// right size, finite, with a non-NaN residual; a problem written back (storages 0 and 1,
// %.17g) reads back bit-equal; the input without its last byte is refused or reads as the same
// problem (a cut never changes a value).
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>

#include "dc/core/error.hpp"
#include "dc/lcp/fc2d_dat_file.hpp"
#include "dc/lcp/lcp_solver.hpp"
#include "fuzz_common.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  try {
    (void)dc::detect_dat_kind(text, "fuzz.dat");
  } catch (const dc::IoError&) {
  }
  dc::Fc2dProblem p;
  try {
    p = dc::parse_fc2d_dat(text, "fuzz.dat").problem;
  } catch (const dc::IoError&) {
    return 0;
  }
  dc::LcpProblem lcp;
  try {
    p.validate();
    lcp = dc::fc2d_to_lcp(p);
    lcp.validate();
  } catch (const dc::InvalidArgument&) {
    dc::fuzz::property_failed("parse_fc2d_dat accepted a problem that does not validate");
  }
  auto same = [&](const dc::Fc2dProblem& o) {
    return Eigen::MatrixXd(o.W) == Eigen::MatrixXd(p.W) && o.q == p.q && o.mu == p.mu;
  };
  for (const dc::Fc2dStorage storage : {dc::Fc2dStorage::SparseBlock, dc::Fc2dStorage::Dense}) {
    if (storage == dc::Fc2dStorage::Dense && p.contacts() > 200) break;  // n² numbers
    try {
      if (!same(dc::parse_fc2d_dat(dc::format_fc2d_dat(p, storage), "back").problem))
        dc::fuzz::property_failed("a written problem does not read back bit-equal");
    } catch (const std::exception&) {  // IoError or InvalidArgument
      dc::fuzz::property_failed("a writer refused, or its reader refused, a problem parse_fc2d_dat accepted");
    }
  }
  try {
    if (!same(dc::parse_fc2d_dat(text.substr(0, size - 1), "cut.dat").problem))
      dc::fuzz::property_failed("the file without its last byte reads as another problem");
  } catch (const dc::IoError&) {
  }
  if (p.contacts() > 6) return 0;
  dc::SolverOptions o;
  o.max_sweeps = 60;
  o.tolerance = 1e-10;
  o.record_theta = false;
  for (const char* name : {"newton", "pgs", "pgs-assembled"}) {
    const dc::SolveResult r = dc::make_solver(name)->solve(lcp, Eigen::VectorXd(), o);
    if (r.lambda.size() != lcp.rows()) dc::fuzz::property_failed("solver returned a wrongly sized lambda");
    if (!r.lambda.allFinite()) dc::fuzz::property_failed("solver returned a non-finite lambda");
    if (std::isnan(r.residual)) dc::fuzz::property_failed("solver returned a NaN residual");
  }
  return 0;
}
