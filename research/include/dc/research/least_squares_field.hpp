#pragma once
// G*, the least-squares grid field of one sample's exact correction — what a perfect network
// of the model's parametrisation would output:
//   G* = argmin_G ‖R G − δ‖₂,   δ = (λ* − λ_prev) per contact pair (N·s),
// R the sample's read-back (ContactReadback: Shepard for residual models, λ_prev times the
// interpolated gain for gain models; G in N·s or dimensionless). CGLS from G = 0 (Björck,
// Numerical Methods for Least Squares Problems, §7.4) for `iterations` iterations: early
// stopping is the regularisation, and nodes no contact sees stay 0. Used by pgs_landscape.hpp
// and by PgsLoss::Field (pgs_trainer.hpp).
#include <vector>

#include "dc/research/pgs_samples.hpp"

namespace dc {

/// G* (2·ny·nx values, NCHW, the model output's layout). InvalidArgument for iterations < 1 or
/// a sample without λ* / λ_prev.
std::vector<float> least_squares_correction_grid(const PgsSample& sample, int iterations);

}  // namespace dc
