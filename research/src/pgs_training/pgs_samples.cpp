// collect_pgs_samples: SimulationGenerator::run (data_generator.cpp) with the problem kept.
// The loop must stay the generator's step for step (collide, assemble, features before the
// solve, oracle from builtin, integrate with λ*); pgs_trainer_test checks that the replayed
// features equal the data set's.
#include "dc/research/pgs_samples.hpp"

#include <exception>
#include <string>

#include "dc/cnn/data_set_oracle_solver.hpp"
#include "dc/cnn/feature_image.hpp"
#include "dc/core/error.hpp"
#include "dc/engine/contact.hpp"
#include "dc/lcp/lcp_solver.hpp"
#include "dc/engine/world.hpp"
#include "dc/warmstart/warm_starter.hpp"

namespace dc {

SphTransferDef readback_transfer_def(const FeatureImageDef& image) {
  SphTransferDef t = image.sph;
  t.grid.channels = FeatureImageBuilder::kLabelChannels;
  t.normalisation = SphNormalisation::Shepard;
  return t;
}

namespace {

std::vector<PgsSample> replay_simulation(const DataSetParams& params, int index, int every, int first_step,
                                         const std::function<bool()>& keep_going, LabelKind readback) {
  std::vector<PgsSample> out;
  SphTransfer transfer(readback_transfer_def(params.image));
  const WorldDef def = params.simulation_scene(index);
  World world(def);
  FeatureImageBuilder images(params.image);
  auto builtin = default_warm_starters().make("builtin");
  const DataSetOracleSolver oracle(params.oracle);
  int recorded = 0;
  for (int s = 0; s < def.time.steps; ++s) {
    if (keep_going && !keep_going()) return out;
    world.collide();
    const LcpProblem& problem = world.assemble();
    const std::vector<Contact>& contacts = world.contacts();
    if (contacts.empty()) {
      world.integrate(Eigen::VectorXd::Zero(0));
      continue;
    }
    // Steps before first_step are replayed (the trajectory needs them) but not kept.
    const bool keep = s >= first_step && recorded % every == 0;
    if (s >= first_step) ++recorded;
    PgsSample sample;
    if (keep) {
      sample.features = Tensor(1, images.feature_channels(), images.ny(), images.nx());
      images.features(world.bodies(), contacts, world.previous_contacts(), &problem,
                      std::span<float>(sample.features.data(), sample.features.size()));
    }
    const Eigen::VectorXd guess = builtin->initial_guess(StepView{world, nullptr});
    const Eigen::VectorXd lambda = oracle.solve(problem, guess).lambda;
    if (!lambda.allFinite())
      throw std::runtime_error("simulation " + std::to_string(index) + ", step " + std::to_string(s) +
                               ": the oracle returned a non-finite lambda");
    if (keep) {
      sample.problem = problem;
      sample.lambda_star = lambda;
      // λ_prev as the cnn starter forms it for a residual model: previous λ by key, 0 if new.
      const auto& prev = world.previous_contacts();
      const std::vector<int> prev_of = match_contacts_by_key(prev, contacts);
      sample.lambda_prev = Eigen::VectorXd::Zero(problem.rows());
      for (std::size_t c = 0; c < contacts.size(); ++c) {
        if (prev_of[c] < 0) continue;
        const Contact& p = prev[static_cast<std::size_t>(prev_of[c])];
        world.constraints().put(static_cast<int>(c), p.lambda_n, p.lambda_t, sample.lambda_prev);
      }
      std::vector<Vec2> points;
      points.reserve(contacts.size());
      for (const Contact& c : contacts) points.push_back(c.point);
      if (readback == LabelKind::Gain) {
        std::vector<double> prev_pairs;
        world.constraints().gather(sample.lambda_prev, prev_pairs);
        sample.readback = ContactReadback::gain(transfer, points, prev_pairs);
      } else {
        sample.readback = ContactReadback(transfer, points);
      }
      sample.simulation = index;
      sample.step = s;
      out.push_back(std::move(sample));
    }
    world.integrate(lambda);
  }
  return out;
}

}  // namespace

std::vector<PgsSample> collect_pgs_samples(const DataSetParams& params, std::span<const int> sims, int every,
                                           const std::function<bool()>& keep_going, int first_step,
                                           LabelKind readback) {
  if (every < 1) throw ConfigError("--every must be >= 1");
  if (first_step < 0) throw ConfigError("--first-step must be >= 0");
  params.validate();
  // Simulations are independent pure functions of (params, index): one per OpenMP worker,
  // concatenated in the order given (the result does not depend on the thread count).
  std::vector<std::vector<PgsSample>> per_sim(sims.size());
  std::exception_ptr error;
#pragma omp parallel for schedule(dynamic, 1)
  for (std::size_t q = 0; q < sims.size(); ++q) {
    try {
      per_sim[q] = replay_simulation(params, sims[q], every, first_step, keep_going, readback);
    } catch (...) {
#pragma omp critical(dc_pgs_samples_error)
      if (!error) error = std::current_exception();
    }
  }
  if (error) std::rethrow_exception(error);
  std::vector<PgsSample> out;
  for (auto& v : per_sim)
    for (PgsSample& s : v) out.push_back(std::move(s));
  return out;
}

}  // namespace dc
