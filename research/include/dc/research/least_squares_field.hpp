#pragma once
// G*, the least-squares grid field of one sample's exact correction: the best field of a
// model's own output space, i.e. what a perfect network of that parametrisation would output.
//
//   G* = argmin_G ‖R G − δ‖₂,   δ = (λ* − λ_prev) per contact pair (N·s),
//
// R the sample's read-back (ContactReadback: Shepard weights for residual models, λ_prev times
// the interpolated gain for gain models; G in N·s or dimensionless). Solved by CGLS from G = 0
// (Björck, Numerical Methods for Least Squares Problems, §7.4) for `iterations` iterations:
// early stopping is the regularisation (few iterations give a smooth field, many the
// minimum-norm fit), and the grid nodes no contact sees stay 0.
//
// Used by the landscape probe (pgs_landscape.hpp: is the path to G* downhill?) and by the
// field loss of training through PGS (pgs_trainer.hpp, PgsLoss::Field: regress the network
// output on G*).
#include <vector>

#include "dc/research/pgs_samples.hpp"

namespace dc {

/// G* (2·ny·nx values, NCHW, the model output's layout). InvalidArgument for iterations < 1 or
/// a sample without λ* / λ_prev.
std::vector<float> least_squares_correction_grid(const PgsSample& sample, int iterations);

}  // namespace dc
