#pragma once
// The training examples of the solver-unrolled loss (pgs_trainer.hpp): per step, the feature
// image, the LCP the guess is for (J, M⁻¹, b, bounds, μ, contact constraints), builtin's
// λ_prev, λ* and the contact read-back. A data set stores its DataSetParams and simulation i is
// a pure function of (params, i), so collect_pgs_samples replays the simulations with the
// generator's own loop and keeps every `every`-th recorded step's problem: the solver-trained
// and regression-trained models see the same samples (the replayed feature images equal the
// file's), and the file need not store J/b/bounds per step.
#include <Eigen/Core>
#include <functional>
#include <span>
#include <vector>

#include "dc/cnn/contact_readback.hpp"
#include "dc/cnn/data_set.hpp"
#include "dc/lcp/lcp_problem.hpp"
#include "dc/learning/labels.hpp"
#include "dc/learning/tensor.hpp"

namespace dc {

struct PgsSample {
  Tensor features;               ///< [1, Cf, ny, nx] raw features (the data set's)
  LcpProblem problem;            ///< this step's LCP (A not formed)
  Eigen::VectorXd lambda_prev;   ///< rows: the previous step's λ by contact key, 0 for new contacts
  Eigen::VectorXd lambda_star;   ///< rows: the oracle's λ* (as in the data set)
  ContactReadback readback;      ///< read-back at this step's contact points (Shepard or gain)
  int simulation = 0;            ///< simulation index in the data set
  int step = 0;                  ///< step index within it
};

/// Replays simulations `sims` of `params` and returns every `every`-th sample of each,
/// counted from the first step ≥ `first_step` (the samples train's --every and --first-step
/// keep). `keep_going` is polled between steps (false: stop, return what is complete).
/// ConfigError for every < 1 or first_step < 0. `readback` is the label kind of the model the
/// samples train (Gain: ContactReadback::gain on each sample's λ_prev; otherwise Shepard).
std::vector<PgsSample> collect_pgs_samples(const DataSetParams& params, std::span<const int> sims, int every,
                                           const std::function<bool()>& keep_going = {}, int first_step = 0,
                                           LabelKind readback = LabelKind::Residual);

/// The read-back transfer of a feature image: its kernel, d, h and box, two channels, Shepard.
SphTransferDef readback_transfer_def(const FeatureImageDef& image);

}  // namespace dc
