#include "dc/learning/trainer.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstring>
#include <limits>
#include <set>

#include "dc/core/error.hpp"
#include "dc/core/rng.hpp"
#include "dc/learning/initializer.hpp"
#include "dc/learning/lr_schedule.hpp"
#include "dc/learning/mse_loss.hpp"
#include "dc/learning/optimizer.hpp"
#include "dc/learning/shuffle_stream.hpp"

namespace dc {

void TrainDef::validate() const {
  if (epochs < 1) throw ConfigError("train: epochs must be >= 1, got " + std::to_string(epochs));
  if (batch_size < 1) throw ConfigError("train: batch_size must be >= 1, got " + std::to_string(batch_size));
  if (!(learning_rate > 0.0)) throw ConfigError("train: learning_rate must be > 0");
  if (!(momentum >= 0.0 && momentum < 1.0)) throw ConfigError("train: momentum must be in [0, 1)");
  if (!(weight_decay >= 0.0)) throw ConfigError("train: weight_decay must be >= 0");
  if (!(validation_fraction >= 0.0 && validation_fraction < 1.0))
    throw ConfigError("train: validation_fraction must be in [0, 1)");
  if (shuffle_buffer < 1) throw ConfigError("train: shuffle_buffer must be >= 1 sample");
  (void)make_lr_schedule(schedule, learning_rate, epochs);
  (void)make_initializer(init);
}

Trainer::Trainer(TrainDef def) : def_(std::move(def)) { def_.validate(); }

std::vector<int> Trainer::pick_validation_simulations(std::span<const TrainingSample> data, double fraction,
                                                      Rng& rng) {
  std::vector<int> sims(data.size());
  for (std::size_t i = 0; i < data.size(); ++i) sims[i] = data[i].simulation;
  return pick_validation_simulations(std::span<const int>(sims), fraction, rng);
}

std::vector<int> Trainer::pick_validation_simulations(std::span<const int> sample_simulations, double fraction,
                                                      Rng& rng) {
  const std::set<int> ids(sample_simulations.begin(), sample_simulations.end());
  std::vector<int> all(ids.begin(), ids.end());
  const int S = static_cast<int>(all.size());
  if (fraction <= 0.0 || S < 2) return {};
  const int k = std::clamp(static_cast<int>(std::floor(fraction * S + 0.5)), 1, S - 1);
  // Partial Fisher–Yates: the first k positions become a uniform random subset.
  for (int i = 0; i < k; ++i) {
    const int j = i + static_cast<int>(rng.uniform_int(static_cast<std::uint64_t>(S - i)));
    std::swap(all[static_cast<std::size_t>(i)], all[static_cast<std::size_t>(j)]);
  }
  std::vector<int> val(all.begin(), all.begin() + k);
  std::sort(val.begin(), val.end());
  return val;
}

namespace {

/// Samples per read of the training split (one run of consecutive rows of a data-set file,
/// ≈ 1.7 MB at the default grid): large enough for sequential reads, small against the
/// shuffle buffer so that the buffer mixes many blocks.
constexpr std::size_t kReadBlock = 16;

/// Checks every sample against the network before any work, so a bad sample fails with its
/// index instead of deep inside an epoch. Returns the weight channels shared by all weighted
/// samples (0: no sample has weights; 1 or C_out otherwise, see TrainingSample).
int check_samples(std::span<const TrainingSample> data, const Shape& xs, const Shape& ys) {
  int wc = 0;
  for (std::size_t i = 0; i < data.size(); ++i) {
    const TrainingSample& s = data[i];
    const std::string where = "Trainer::train: sample " + std::to_string(i);
    require_shape(s.features.shape(), xs, where + " features");
    require_shape(s.labels.shape(), ys, where + " labels");
    if (!s.weights.empty()) {
      const int c = s.weights.c();
      if (!(s.weights.shape() == ys) && !(s.weights.shape() == Shape{1, 1, ys.h, ys.w}))
        throw InvalidArgument(where + " weights: shape " + s.weights.shape().str() + " fits neither labels nor C = 1");
      if (wc != 0 && c != wc) throw InvalidArgument(where + " weights: channel count differs from earlier samples");
      wc = c;
    }
  }
  return wc;
}

/// Sample indices of the two sides of the split, in data order.
struct SampleSplit {
  std::vector<std::size_t> train, validation;
};

/// Splits the samples by simulation (whole simulations on one side: consecutive frames of a
/// simulation are nearly identical, so frames on both sides would make the validation loss
/// a training loss; docs/design.md §4). Fills result.train_simulations.
SampleSplit split_by_simulation(std::span<const int> sample_simulations, const std::vector<int>& validation_simulations,
                                TrainResult& result) {
  const std::set<int> val_ids(validation_simulations.begin(), validation_simulations.end());
  SampleSplit split;
  std::set<int> tr_ids;
  for (std::size_t i = 0; i < sample_simulations.size(); ++i) {
    if (val_ids.count(sample_simulations[i])) {
      split.validation.push_back(i);
    } else {
      split.train.push_back(i);
      tr_ids.insert(sample_simulations[i]);
    }
  }
  result.train_simulations.assign(tr_ids.begin(), tr_ids.end());
  return split;
}

/// The model's channel standardisation, from the training split only: statistics that saw
/// the validation samples would leak them into the inputs the validation loss is measured on.
/// One pass in data order, a read block at a time (the sums of ChannelStats::compute).
void standardise_from_training_split(Model& model, const SampleSource& data, const std::vector<std::size_t>& train) {
  ChannelStatsAccumulator fx, fy;
  Tensor x, y, w;
  for (std::size_t first = 0; first < train.size(); first += kReadBlock) {
    const std::size_t count = std::min(kReadBlock, train.size() - first);
    data.read(std::span<const std::size_t>(train).subspan(first, count), x, y, w);
    fx.add(x);
    fy.add(y);
  }
  model.input_stats = fx.finish();
  model.output_stats = fy.finish();
}

/// The shapes of the source against the network's, and its weight channels (0, 1 or C_out).
void check_source(const SampleSource& data, const Shape& xs, const Shape& ys) {
  require_shape(data.feature_shape(), xs, "Trainer::train: features");
  require_shape(data.label_shape(), ys, "Trainer::train: labels");
  const int wc = data.weight_channels();
  if (wc != 0 && wc != 1 && wc != ys.c)
    throw InvalidArgument("Trainer::train: " + std::to_string(wc) + " weight channels fit neither labels nor C = 1");
}

/// Continues a saved run: the weights are the model's (loaded from the checkpoint); the
/// random stream and the momentum continue from where the saved run finished its last
/// epoch, and its history is taken over. Returns the first epoch to run.
int restore_training_state(const TrainState& resume, Rng& rng, Sgd& sgd, const std::vector<ParamRef>& params,
                           TrainResult& result) {
  if (resume.rng_type != rng.algorithm() || resume.rng_state.size() != rng.save_state().size())
    throw InvalidArgument("Trainer::train: resume state has a random stream of another type or size");
  rng.restore_state(resume.rng_type, resume.rng_state);
  if (!resume.velocity.empty()) {
    if (resume.velocity.size() != params.size())
      throw InvalidArgument("Trainer::train: resume state has " + std::to_string(resume.velocity.size()) +
                            " momentum buffers for " + std::to_string(params.size()) + " parameters");
    std::vector<Eigen::VectorXf> v(params.size());
    for (std::size_t i = 0; i < params.size(); ++i) {
      if (resume.velocity[i].size() != params[i].value->size())
        throw InvalidArgument("Trainer::train: resume momentum of " + params[i].name + " has the wrong size");
      v[i] = Eigen::Map<const Eigen::VectorXf>(resume.velocity[i].data(),
                                                static_cast<Eigen::Index>(resume.velocity[i].size()));
    }
    sgd.set_velocity(std::move(v));
  }
  if (resume.epochs_done < 0 || static_cast<std::size_t>(resume.epochs_done) != resume.history.size())
    throw InvalidArgument("Trainer::train: resume state's history does not match its epoch count");
  result.history = resume.history;
  return resume.epochs_done;
}

/// The minibatch work of a run: one epoch of SGD steps over the training stream, and the
/// validation loss. Holds the batch buffers (reused by every batch, training and validation
/// alike) and, with a process group, the buffer of the gradient sum.
class MinibatchLoop {
 public:
  MinibatchLoop(Network& net, const std::vector<ParamRef>& params, Sgd& sgd, ShuffleStream& train, int wc,
                const Shape& ys, int batch_size, const DataParallelGroup* group,
                const std::function<bool()>& keep_going)
      : net_(net), params_(params), sgd_(sgd), train_(train), wc_(wc), ys_(ys), batch_size_(batch_size),
        group_(group != nullptr && group->size() > 1 ? group : nullptr), keep_going_(keep_going) {
    for (const ParamRef& p : params_) grad_count_ += p.grad->size();
  }

  /// One epoch: a forward, backward and SGD step per minibatch of the stream (its epoch
  /// started). Returns false when keep_going stopped it; the unfinished epoch is then
  /// abandoned (the caller keeps the last finished epoch's state). `loss_sum` receives
  /// Σ b · (the batch's mean loss).
  bool train_epoch(double lr, double& loss_sum) {
    const std::size_t n = train_.size();
    for (std::size_t first = 0; first < n; first += static_cast<std::size_t>(batch_size_)) {
      // One process polls here; a group polls inside the batch, so all stop at the same batch.
      if (!group_ && keep_going_ && !keep_going_()) return false;
      const int b = static_cast<int>(std::min<std::size_t>(static_cast<std::size_t>(batch_size_), n - first));
      if (group_) {
        bool stop = false;
        loss_sum += b * parallel_batch(b, stop);
        if (stop) return false;
      } else {
        loss_sum += b * local_batch(b);
      }
      sgd_.step(params_, lr);
    }
    return true;
  }

  /// Mean loss over the validation samples `val` of `data` in inference mode (no dropout, no
  /// gradient), read in data order in batches of the training batch size (the same sums
  /// every epoch) and standardised with the model's statistics.
  double validation_loss(const SampleSource& data, const std::vector<std::size_t>& val, const ChannelStats& in,
                         const ChannelStats& out) {
    double vsum = 0.0;
    for (std::size_t first = 0; first < val.size(); first += static_cast<std::size_t>(batch_size_)) {
      const std::size_t b = std::min<std::size_t>(static_cast<std::size_t>(batch_size_), val.size() - first);
      data.read(std::span<const std::size_t>(val).subspan(first, b), xb_, yb_, wb_);
      in.apply(xb_);
      out.apply(yb_);
      vsum += static_cast<double>(b) * mse_(net_.forward(xb_, false), yb_, wc_ > 0 ? &wb_ : nullptr);
    }
    return vsum / static_cast<double>(val.size());
  }

 private:
  /// This process alone: the batch's forward and backward; returns its loss.
  double local_batch(int b) {
    train_.next_batch(b, 0, b, xb_, yb_, wb_);
    const Tensor& pred = net_.forward(xb_, true);
    const double loss = mse_(pred, yb_, wc_ > 0 ? &wb_ : nullptr, &grad_);
    net_.backward(grad_);
    return loss;
  }

  /// Data-parallel minibatch (data_parallel.hpp): this process's shard forward and backward,
  /// then one sum over the group of [den·∇ for every parameter, num, den, stop votes].
  /// Returns the whole batch's loss; `stop` = some process's keep_going said no.
  double parallel_batch(int b, bool& stop) {
    const int K = group_->size(), r = group_->rank();
    const int lo = static_cast<int>(static_cast<long>(b) * r / K), hi = static_cast<int>(static_cast<long>(b) * (r + 1) / K);
    // An empty shard (b < K) still runs one sample with weight 0: its dropout layers must
    // draw the batch's masks like everyone else's.
    const bool empty = hi == lo;
    const int offset = empty ? 0 : lo, count = empty ? 1 : hi - lo;
    train_.next_batch(b, offset, count, xb_, yb_, wb_);  // every process takes the whole batch off the stream
    net_.set_batch_window(offset, b);
    const Tensor& pred = net_.forward(xb_, true);
    net_.set_batch_window(0, 0);
    const double loss = mse_(pred, yb_, wc_ > 0 ? &wb_ : nullptr, &grad_);
    net_.backward(grad_);
    // The shard's MSE denominator: Σ of the weight of every prediction element.
    double den = 0.0;
    if (!empty) {
      if (wc_ == 0) {
        den = static_cast<double>(pred.size());
      } else {
        for (std::size_t i = 0; i < wb_.size(); ++i) den += wb_[i];
        if (wc_ == 1 && ys_.c != 1) den *= ys_.c;
      }
    }
    reduce_.assign(grad_count_ + 3, 0.0);
    std::size_t k = 0;
    for (const ParamRef& p : params_)
      for (std::size_t i = 0; i < p.grad->size(); ++i) reduce_[k++] = den * static_cast<double>((*p.grad)[i]);
    reduce_[k] = den * loss;
    reduce_[k + 1] = den;
    reduce_[k + 2] = keep_going_ && !keep_going_() ? 1.0 : 0.0;
    group_->sum(reduce_);
    stop = reduce_[k + 2] > 0.0;
    const double total = reduce_[k + 1];
    const double scale = total > 0.0 ? 1.0 / total : 0.0;
    k = 0;
    for (const ParamRef& p : params_)
      for (std::size_t i = 0; i < p.grad->size(); ++i) (*p.grad)[i] = static_cast<float>(reduce_[k++] * scale);
    return reduce_[k] * scale;
  }

  Network& net_;
  const std::vector<ParamRef>& params_;
  Sgd& sgd_;
  ShuffleStream& train_;
  const int wc_;
  const Shape ys_;
  const int batch_size_;
  const DataParallelGroup* const group_;  // null: this process alone (no group, or a group of 1)
  const std::function<bool()>& keep_going_;
  const MseLoss mse_{};
  Tensor xb_, yb_, wb_, grad_;
  std::size_t grad_count_ = 0;   // parameters in all: the gradient part of reduce_
  std::vector<double> reduce_;   // the group sum's buffer
};

/// What the epoch callback checkpoints: the epochs done, their reports, the stream after the
/// epoch's last draw and the momentum, so that a resume continues bit-identically.
void record_checkpoint_state(TrainState& state, int epochs_done, const TrainResult& result, const Rng& rng,
                             const Sgd& sgd) {
  state.epochs_done = epochs_done;
  state.history = result.history;
  state.rng_state = rng.save_state();
  state.velocity.clear();
  for (const Eigen::VectorXf& v : sgd.velocity()) state.velocity.emplace_back(v.data(), v.data() + v.size());
}

}  // namespace

TrainResult Trainer::train(Model& model, std::span<const TrainingSample> data, const Callback& on_epoch) {
  const StateCallback cb = on_epoch ? StateCallback([&](const EpochReport& r, const TrainState&) { return on_epoch(r); })
                                    : StateCallback();
  return train(model, data, cb, nullptr, {});
}

TrainResult Trainer::train(Model& model, std::span<const TrainingSample> data, const StateCallback& on_epoch,
                           const TrainState* resume, const std::function<bool()>& keep_going) {
  if (data.empty()) throw InvalidArgument("Trainer::train: empty data set");
  const Network& net = model.network();
  (void)check_samples(data, net.input_shape(), net.output_shape());  // names the first bad sample
  const InMemorySamples source(data);
  return train(model, source, on_epoch, resume, keep_going);
}

// The steps of a run, in the order the random stream is drawn (trainer.hpp "Determinism"):
// the split, then the initial weights (or the restored stream), then per epoch the shuffle
// and the dropout masks of its batches. Reordering any of them changes every weight.
TrainResult Trainer::train(Model& model, const SampleSource& data, const StateCallback& on_epoch,
                           const TrainState* resume, const std::function<bool()>& keep_going) {
  if (data.size() == 0) throw InvalidArgument("Trainer::train: empty data set");
  Network& net = model.network();
  const Shape xs = net.input_shape(), ys = net.output_shape();
  check_source(data, xs, ys);
  const int wc = data.weight_channels();

  Rng rng(def_.seed);
  TrainResult result;
  std::vector<int> sims(data.size());
  for (std::size_t i = 0; i < sims.size(); ++i) sims[i] = data.simulation(i);
  result.validation_simulations = pick_validation_simulations(std::span<const int>(sims), def_.validation_fraction, rng);
  if (resume && resume->validation_simulations != result.validation_simulations)
    throw InvalidArgument("Trainer::train: resume state belongs to another train/validation split "
                          "(different data set, seed or validation fraction)");
  const SampleSplit split = split_by_simulation(sims, result.validation_simulations, result);
  standardise_from_training_split(model, data, split.train);
  ShuffleStream train(data, split.train, model.input_stats, model.output_stats, def_.shuffle_buffer, kReadBlock);

  Sgd sgd(SgdDef{def_.momentum, def_.weight_decay});
  const std::vector<ParamRef> params = net.parameters();
  int first_epoch = 0;
  if (resume) first_epoch = restore_training_state(*resume, rng, sgd, params, result);
  else if (def_.initialize) net.initialize(*make_initializer(def_.init), rng);
  net.set_rng(&rng);  // the dropout masks come from the run's stream too
  const auto schedule = make_lr_schedule(def_.schedule, def_.learning_rate, def_.epochs);
  MinibatchLoop loop(net, params, sgd, train, wc, ys, def_.batch_size, group_, keep_going);
  TrainState state;  // handed to the callback after every epoch
  state.validation_simulations = result.validation_simulations;
  state.rng_type = rng.algorithm();

  for (int epoch = first_epoch; epoch < def_.epochs; ++epoch) {
    const auto t0 = std::chrono::steady_clock::now();
    train.start_epoch(rng);
    const double lr = schedule->rate(epoch);
    double loss_sum = 0.0;
    if (!loop.train_epoch(lr, loss_sum)) break;  // stopped: the unfinished epoch is not reported
    EpochReport rep;
    rep.epoch = epoch;
    rep.learning_rate = lr;
    rep.train_loss = loss_sum / static_cast<double>(std::max<std::size_t>(1, train.size()));
    rep.validation_loss = split.validation.empty()
                              ? std::numeric_limits<double>::quiet_NaN()
                              : loop.validation_loss(data, split.validation, model.input_stats, model.output_stats);
    rep.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    result.history.push_back(rep);
    if (on_epoch) {
      record_checkpoint_state(state, epoch + 1, result, rng, sgd);
      if (!on_epoch(rep, state)) break;
    }
  }
  net.set_rng(nullptr);
  return result;
}

}  // namespace dc
