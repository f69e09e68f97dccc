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

namespace dc {

void TrainDef::validate() const {
  if (epochs < 1) throw ConfigError("train: epochs must be >= 1, got " + std::to_string(epochs));
  if (batch_size < 1) throw ConfigError("train: batch_size must be >= 1, got " + std::to_string(batch_size));
  if (!(learning_rate > 0.0)) throw ConfigError("train: learning_rate must be > 0");
  if (!(momentum >= 0.0 && momentum < 1.0)) throw ConfigError("train: momentum must be in [0, 1)");
  if (!(weight_decay >= 0.0)) throw ConfigError("train: weight_decay must be >= 0");
  if (!(validation_fraction >= 0.0 && validation_fraction < 1.0))
    throw ConfigError("train: validation_fraction must be in [0, 1)");
  (void)make_lr_schedule(schedule, learning_rate, epochs);
  (void)make_initializer(init);
}

Trainer::Trainer(TrainDef def) : def_(std::move(def)) { def_.validate(); }

std::vector<int> Trainer::pick_validation_simulations(std::span<const TrainingSample> data, double fraction,
                                                      Rng& rng) {
  std::set<int> ids;
  for (const TrainingSample& s : data) ids.insert(s.simulation);
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

// Standardised copies of a subset, packed as [N, C, H, W] so minibatches are memcpy's.
struct Packed {
  Tensor x, y, w;  // w empty if no sample has weights
  int n = 0;
};

Packed pack(std::span<const TrainingSample> data, const std::vector<std::size_t>& idx, const ChannelStats& in,
            const ChannelStats& out, const Shape& xs, const Shape& ys, int wc) {
  Packed p;
  p.n = static_cast<int>(idx.size());
  p.x.resize(xs.with_batch(p.n));
  p.y.resize(ys.with_batch(p.n));
  if (wc > 0) p.w.resize({p.n, wc, ys.h, ys.w});
  for (int k = 0; k < p.n; ++k) {
    const TrainingSample& s = data[idx[static_cast<std::size_t>(k)]];
    std::memcpy(p.x.sample(k), s.features.data(), sizeof(float) * xs.sample_count());
    std::memcpy(p.y.sample(k), s.labels.data(), sizeof(float) * ys.sample_count());
    if (wc > 0) {
      const std::size_t len = static_cast<std::size_t>(wc) * ys.plane();
      if (s.weights.empty()) std::fill(p.w.sample(k), p.w.sample(k) + len, 1.0f);
      else std::memcpy(p.w.sample(k), s.weights.data(), sizeof(float) * len);
    }
  }
  if (p.n > 0) {
    in.apply(p.x);
    out.apply(p.y);
  }
  return p;
}

void gather(const Tensor& src, const std::vector<std::size_t>& order, std::size_t first, int count, Tensor& dst) {
  const std::size_t len = src.shape().sample_count();
  dst.resize(src.shape().with_batch(count));
  for (int k = 0; k < count; ++k)
    std::memcpy(dst.sample(k), src.sample(static_cast<int>(order[first + static_cast<std::size_t>(k)])),
                sizeof(float) * len);
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
  Network& net = model.network();
  const Shape xs = net.input_shape(), ys = net.output_shape();
  int wc = 0;  // weight channels (0: unweighted)
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

  Rng rng(def_.seed);
  TrainResult result;
  result.validation_simulations = pick_validation_simulations(data, def_.validation_fraction, rng);
  if (resume && resume->validation_simulations != result.validation_simulations)
    throw InvalidArgument("Trainer::train: resume state belongs to another train/validation split "
                          "(different data set, seed or validation fraction)");
  const std::set<int> val_ids(result.validation_simulations.begin(), result.validation_simulations.end());
  std::vector<std::size_t> tr_idx, va_idx;
  std::set<int> tr_ids;
  for (std::size_t i = 0; i < data.size(); ++i) {
    if (val_ids.count(data[i].simulation)) {
      va_idx.push_back(i);
    } else {
      tr_idx.push_back(i);
      tr_ids.insert(data[i].simulation);
    }
  }
  result.train_simulations.assign(tr_ids.begin(), tr_ids.end());

  // Standardisation from the training split only.
  std::vector<const Tensor*> fx, fy;
  for (std::size_t i : tr_idx) {
    fx.push_back(&data[i].features);
    fy.push_back(&data[i].labels);
  }
  model.input_stats = ChannelStats::compute(fx);
  model.output_stats = ChannelStats::compute(fy);
  const Packed train = pack(data, tr_idx, model.input_stats, model.output_stats, xs, ys, wc);
  const Packed val = pack(data, va_idx, model.input_stats, model.output_stats, xs, ys, wc);

  Sgd sgd(SgdDef{def_.momentum, def_.weight_decay});
  std::vector<ParamRef> params = net.parameters();
  int first_epoch = 0;
  if (resume) {
    // The weights are the model's (loaded from the checkpoint); the stream and the momentum
    // continue from where the saved run finished its last epoch.
    if (resume->rng_type != rng.algorithm() || resume->rng_state.size() != rng.save_state().size())
      throw InvalidArgument("Trainer::train: resume state has a random stream of another type or size");
    rng.restore_state(resume->rng_type, resume->rng_state);
    if (!resume->velocity.empty()) {
      if (resume->velocity.size() != params.size())
        throw InvalidArgument("Trainer::train: resume state has " + std::to_string(resume->velocity.size()) +
                              " momentum buffers for " + std::to_string(params.size()) + " parameters");
      std::vector<Eigen::VectorXf> v(params.size());
      for (std::size_t i = 0; i < params.size(); ++i) {
        if (resume->velocity[i].size() != params[i].value->size())
          throw InvalidArgument("Trainer::train: resume momentum of " + params[i].name + " has the wrong size");
        v[i] = Eigen::Map<const Eigen::VectorXf>(resume->velocity[i].data(),
                                                  static_cast<Eigen::Index>(resume->velocity[i].size()));
      }
      sgd.set_velocity(std::move(v));
    }
    if (resume->epochs_done < 0 || static_cast<std::size_t>(resume->epochs_done) != resume->history.size())
      throw InvalidArgument("Trainer::train: resume state's history does not match its epoch count");
    first_epoch = resume->epochs_done;
    result.history = resume->history;
  } else if (def_.initialize) {
    net.initialize(*make_initializer(def_.init), rng);
  }
  net.set_rng(&rng);
  const auto schedule = make_lr_schedule(def_.schedule, def_.learning_rate, def_.epochs);
  const MseLoss mse;
  std::vector<std::size_t> order(static_cast<std::size_t>(train.n));
  Tensor xb, yb, wb, grad;
  TrainState state;  // handed to the callback after every epoch

  // Data-parallel minibatch (data_parallel.hpp): this process's shard forward and backward,
  // then one sum over the group of [den·∇ for every parameter, num, den, stop votes].
  // Returns the whole batch's loss; `stop` = some process's keep_going said no.
  const bool parallel = group_ != nullptr && group_->size() > 1;
  std::size_t grad_count = 0;
  for (const ParamRef& p : params) grad_count += p.grad->size();
  std::vector<double> reduce;
  const auto parallel_batch = [&](int b, std::size_t first, bool& stop) -> double {
    const int K = group_->size(), r = group_->rank();
    const int lo = static_cast<int>(static_cast<long>(b) * r / K), hi = static_cast<int>(static_cast<long>(b) * (r + 1) / K);
    // An empty shard (b < K) still runs one sample with weight 0: its dropout layers must
    // draw the batch's masks like everyone else's.
    const bool empty = hi == lo;
    const int offset = empty ? 0 : lo, count = empty ? 1 : hi - lo;
    gather(train.x, order, first + static_cast<std::size_t>(offset), count, xb);
    gather(train.y, order, first + static_cast<std::size_t>(offset), count, yb);
    if (wc > 0) gather(train.w, order, first + static_cast<std::size_t>(offset), count, wb);
    net.set_batch_window(offset, b);
    const Tensor& pred = net.forward(xb, true);
    net.set_batch_window(0, 0);
    const double loss = mse(pred, yb, wc > 0 ? &wb : nullptr, &grad);
    net.backward(grad);
    // The shard's MSE denominator: Σ of the weight of every prediction element.
    double den = 0.0;
    if (!empty) {
      if (wc == 0) {
        den = static_cast<double>(pred.size());
      } else {
        for (std::size_t i = 0; i < wb.size(); ++i) den += wb[i];
        if (wc == 1 && ys.c != 1) den *= ys.c;
      }
    }
    reduce.assign(grad_count + 3, 0.0);
    std::size_t k = 0;
    for (const ParamRef& p : params)
      for (std::size_t i = 0; i < p.grad->size(); ++i) reduce[k++] = den * static_cast<double>((*p.grad)[i]);
    reduce[k] = den * loss;
    reduce[k + 1] = den;
    reduce[k + 2] = keep_going && !keep_going() ? 1.0 : 0.0;
    group_->sum(reduce);
    stop = reduce[k + 2] > 0.0;
    const double total = reduce[k + 1];
    const double scale = total > 0.0 ? 1.0 / total : 0.0;
    k = 0;
    for (const ParamRef& p : params)
      for (std::size_t i = 0; i < p.grad->size(); ++i) (*p.grad)[i] = static_cast<float>(reduce[k++] * scale);
    return reduce[k] * scale;
  };
  state.validation_simulations = result.validation_simulations;
  state.rng_type = rng.algorithm();

  for (int epoch = first_epoch; epoch < def_.epochs; ++epoch) {
    const auto t0 = std::chrono::steady_clock::now();
    for (std::size_t i = 0; i < order.size(); ++i) order[i] = i;
    for (std::size_t i = order.size(); i > 1; --i)  // Fisher–Yates
      std::swap(order[i - 1], order[rng.uniform_int(i)]);
    const double lr = schedule->rate(epoch);
    double loss_sum = 0.0;
    bool stopped = false;
    for (std::size_t first = 0; first < order.size(); first += static_cast<std::size_t>(def_.batch_size)) {
      if (!parallel && keep_going && !keep_going()) {  // abandon the unfinished epoch (the caller keeps the last state)
        stopped = true;
        break;
      }
      const int b = static_cast<int>(std::min<std::size_t>(static_cast<std::size_t>(def_.batch_size), order.size() - first));
      if (parallel) {
        bool stop = false;
        loss_sum += b * parallel_batch(b, first, stop);
        if (stop) {
          stopped = true;
          break;
        }
        sgd.step(params, lr);
        continue;
      }
      gather(train.x, order, first, b, xb);
      gather(train.y, order, first, b, yb);
      if (wc > 0) gather(train.w, order, first, b, wb);
      const Tensor& pred = net.forward(xb, true);
      loss_sum += b * mse(pred, yb, wc > 0 ? &wb : nullptr, &grad);
      net.backward(grad);
      sgd.step(params, lr);
    }
    if (stopped) break;
    EpochReport rep;
    rep.epoch = epoch;
    rep.learning_rate = lr;
    rep.train_loss = loss_sum / std::max(1, train.n);
    rep.validation_loss = std::numeric_limits<double>::quiet_NaN();
    if (val.n > 0) {
      double vsum = 0.0;
      std::vector<std::size_t> vorder(static_cast<std::size_t>(val.n));
      for (std::size_t i = 0; i < vorder.size(); ++i) vorder[i] = i;
      for (std::size_t first = 0; first < vorder.size(); first += static_cast<std::size_t>(def_.batch_size)) {
        const int b = static_cast<int>(std::min<std::size_t>(static_cast<std::size_t>(def_.batch_size), vorder.size() - first));
        gather(val.x, vorder, first, b, xb);
        gather(val.y, vorder, first, b, yb);
        if (wc > 0) gather(val.w, vorder, first, b, wb);
        vsum += b * mse(net.forward(xb, false), yb, wc > 0 ? &wb : nullptr);
      }
      rep.validation_loss = vsum / val.n;
    }
    rep.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    result.history.push_back(rep);
    if (on_epoch) {
      state.epochs_done = epoch + 1;
      state.history = result.history;
      state.rng_state = rng.save_state();
      state.velocity.clear();
      for (const Eigen::VectorXf& v : sgd.velocity()) state.velocity.emplace_back(v.data(), v.data() + v.size());
      if (!on_epoch(rep, state)) break;
    }
  }
  net.set_rng(nullptr);
  return result;
}

}  // namespace dc
