#include "dc/learning/network.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <sstream>

#include "dc/core/error.hpp"
#include "dc/learning/layers/concat.hpp"
#include "dc/learning/layers/conv2d.hpp"
#include "dc/learning/layers/dense.hpp"
#include "dc/learning/layers/dropout.hpp"
#include "dc/learning/layers/relu.hpp"
#include "dc/learning/layers/upsample.hpp"
#include "thread_cpu_time.hpp"

namespace dc {

Network::Network(ArchSpec arch, const Shape& in) : arch_(std::move(arch)), in_{1, in.c, in.h, in.w} {
  if (in_.c <= 0 || in_.h <= 0 || in_.w <= 0) throw ConfigError("network: empty input shape " + in_.str());
  if (arch_.layers.empty()) throw ConfigError("network: architecture '" + arch_.name + "' has no layers");
  std::map<std::string, int> index{{"input", -1}};
  auto shape_of = [&](int j) { return j < 0 ? in_ : nodes_[static_cast<std::size_t>(j)].out; };
  for (std::size_t i = 0; i < arch_.layers.size(); ++i) {
    const LayerSpec& s = arch_.layers[i];
    const std::string where = "arch '" + arch_.name + "' layer " + std::to_string(i) + " '" + s.name + "'";
    if (index.count(s.name)) throw ConfigError(where + ": duplicate node name");
    Node node;
    if (s.inputs.empty()) {
      node.inputs.push_back(static_cast<int>(i) - 1);
    } else {
      for (const std::string& name : s.inputs) {
        auto it = index.find(name);
        if (it == index.end()) throw ConfigError(where + ": unknown input '" + name + "'");
        node.inputs.push_back(it->second);
      }
    }
    std::vector<Shape> ins;
    for (int j : node.inputs) ins.push_back(shape_of(j));
    try {
      const Shape x = concat_shape(ins);
      if (s.type == "conv") {
        node.layer = std::make_unique<Conv2d>(x.c, s.out, s.kernel, s.stride, s.relu);
      } else if (s.type == "relu") {
        node.layer = std::make_unique<ReLU>();
      } else if (s.type == "dropout") {
        node.layer = std::make_unique<Dropout>(s.rate);
      } else if (s.type == "dense") {
        const Shape out = s.out_shape.empty() ? Shape{1, s.out, 1, 1}
                                              : Shape{1, s.out_shape[0], s.out_shape[1], s.out_shape[2]};
        node.layer = std::make_unique<Dense>(static_cast<int>(x.sample_count()), out, s.relu);
      } else if (s.type == "upsample") {
        int h = s.size[0], w = s.size[1];
        if (!s.match.empty()) {
          auto it = index.find(s.match);
          if (it == index.end()) throw ConfigError(where + ": unknown match node '" + s.match + "'");
          h = shape_of(it->second).h;
          w = shape_of(it->second).w;
        }
        node.layer = std::make_unique<Upsample2x>(h, w);
      } else {
        throw ConfigError(where + ": unknown layer type '" + s.type + "'");
      }
      node.out = node.layer->output_shape(x);
    } catch (const InvalidArgument& e) {
      throw ConfigError(where + ": " + e.what());
    }
    index[s.name] = static_cast<int>(i);
    nodes_.push_back(std::move(node));
  }
  out_ = nodes_.back().out;
  act_.resize(nodes_.size());
  grad_.resize(nodes_.size());
  cat_.resize(nodes_.size());
}

const Tensor& Network::input_of(std::size_t i, const Tensor& x) {
  const Node& node = nodes_[i];
  if (node.inputs.size() == 1) {
    const int j = node.inputs[0];
    return j < 0 ? x : act_[static_cast<std::size_t>(j)];
  }
  return cat_[i];
}

const Tensor& Network::forward(const Tensor& x, bool training, std::vector<double>* node_ms) {
  require_shape(x.shape(), in_.with_batch(x.n()), "Network::forward input");
  if (node_ms) node_ms->assign(nodes_.size(), 0.0);
  for (std::size_t i = 0; i < nodes_.size(); ++i) {
    const double t0 = node_ms ? detail::thread_cpu_ms() : 0.0;
    Node& node = nodes_[i];
    if (node.inputs.size() > 1) {
      std::vector<const Tensor*> ins;
      for (int j : node.inputs) ins.push_back(j < 0 ? &x : &act_[static_cast<std::size_t>(j)]);
      concat_channels(ins, cat_[i]);
    }
    node.layer->forward(input_of(i, x), act_[i], training);
    if (node_ms) (*node_ms)[i] = detail::thread_cpu_ms() - t0;
  }
  last_x_ = &x;
  return act_.back();
}

bool Network::forward_at(const Tensor& x, std::span<const int> pixels, Tensor& out) {
  require_shape(x.shape(), in_, "Network::forward_at input");
  const std::size_t last = nodes_.size() - 1;
  auto* head = dynamic_cast<Conv2d*>(nodes_[last].layer.get());
  if (head == nullptr || head->kernel() != 1 || head->stride() != 1) {
    out = forward(x, false);
    return false;
  }
  // Upsample nodes read only by the head are not materialised: the head reads their source.
  std::vector<int> consumers(nodes_.size(), 0);
  for (const Node& n : nodes_)
    for (int j : n.inputs)
      if (j >= 0) ++consumers[static_cast<std::size_t>(j)];
  std::vector<char> virtual_up(nodes_.size(), 0);
  for (int j : nodes_[last].inputs)
    if (j >= 0 && consumers[static_cast<std::size_t>(j)] == 1 &&
        nodes_[static_cast<std::size_t>(j)].layer->type() == "upsample" &&
        nodes_[static_cast<std::size_t>(j)].inputs.size() == 1)
      virtual_up[static_cast<std::size_t>(j)] = 1;
  for (std::size_t i = 0; i < last; ++i) {
    if (virtual_up[i]) continue;
    Node& node = nodes_[i];
    if (node.inputs.size() > 1) {
      std::vector<const Tensor*> ins;
      for (int j : node.inputs) ins.push_back(j < 0 ? &x : &act_[static_cast<std::size_t>(j)]);
      concat_channels(ins, cat_[i]);
    }
    node.layer->forward(input_of(i, x), act_[i], false);
  }
  // The head's input channels as (plane base, width, nearest-upsampled?) triples.
  struct Source {
    const float* data;
    int plane, w;
    bool up;
  };
  std::vector<Source> src;
  for (int j : nodes_[last].inputs) {
    const bool up = j >= 0 && virtual_up[static_cast<std::size_t>(j)];
    const int k = up ? nodes_[static_cast<std::size_t>(j)].inputs[0] : j;
    const Tensor& t = k < 0 ? x : act_[static_cast<std::size_t>(k)];
    for (int c = 0; c < t.c(); ++c)
      src.push_back({t.data() + static_cast<std::size_t>(c) * t.shape().plane(), t.h() * t.w(), t.w(), up});
  }
  out.resize(out_);
  const int W = out_.w, P = out_.h * out_.w, cin = static_cast<int>(src.size()), cout = out_.c;
  const float* wt = head->weight().data();  // [Cout, Cin, 1, 1]
  const float* bias = head->bias().data();
  for (const int p : pixels)
    if (p < 0 || p >= P) throw InvalidArgument("Network::forward_at: pixel " + std::to_string(p) + " outside the output");
  // Blocks of kB pixels, channel-major (v[c·kB + b]), so that the multiply-adds of one
  // channel run as one vector over the block: one pixel's sum is a serial chain (the
  // latency of cin FMAs), kB independent chains fill the pipeline. Each pixel's order is
  // the direct kernel's: fused multiply-adds over the channels from 0, then + bias.
  constexpr int kB = 16;
  std::vector<float> v(static_cast<std::size_t>(cin) * kB);
  float acc[kB];
  for (std::size_t p0 = 0; p0 < pixels.size(); p0 += kB) {
    const int nb = static_cast<int>(std::min<std::size_t>(kB, pixels.size() - p0));
    for (int b = 0; b < kB; ++b) {
      const int p = pixels[p0 + static_cast<std::size_t>(std::min(b, nb - 1))];
      const int Y = p / W, X = p % W;
      for (int c = 0; c < cin; ++c) {
        const Source& s = src[static_cast<std::size_t>(c)];
        v[static_cast<std::size_t>(c * kB + b)] = s.up ? s.data[(Y / 2) * s.w + X / 2] : s.data[Y * s.w + X];
      }
    }
    for (int o = 0; o < cout; ++o) {
      const float* wo = wt + static_cast<std::size_t>(o) * cin;
      for (int b = 0; b < kB; ++b) acc[b] = 0.0f;
      for (int c = 0; c < cin; ++c) {
        const float w = wo[c];
        const float* vc = v.data() + static_cast<std::size_t>(c) * kB;
        for (int b = 0; b < kB; ++b) acc[b] = std::fma(w, vc[b], acc[b]);
      }
      float* yo = out.data() + static_cast<std::size_t>(o) * P;
      for (int b = 0; b < nb; ++b) {
        float r = acc[b] + bias[o];
        if (head->relu()) r = std::max(r, 0.0f);
        yo[pixels[p0 + static_cast<std::size_t>(b)]] = r;
      }
    }
  }
  last_x_ = nullptr;  // no backward after a sparse pass
  return true;
}

void Network::backward(const Tensor& dy) {
  if (last_x_ == nullptr) throw InvalidArgument("Network::backward: no forward pass before");
  require_shape(dy.shape(), act_.back().shape(), "Network::backward dy");
  const Tensor& x = *last_x_;
  // has_grad[j]: grad_[j] already holds a contribution (later ones are added).
  std::vector<char> has_grad(nodes_.size(), 0);
  for (std::size_t ii = nodes_.size(); ii-- > 0;) {
    Node& node = nodes_[ii];
    const Tensor& g = ii + 1 == nodes_.size() ? dy : grad_[ii];
    if (ii + 1 != nodes_.size() && !has_grad[ii]) {
      // A dead end (output not consumed): its parameters get zero gradient.
      for (const ParamRef& p : node.layer->parameters()) p.grad->set_zero();
      continue;
    }
    const Tensor& in = input_of(ii, x);
    if (node.inputs.size() == 1) {
      const int j = node.inputs[0];
      if (j < 0) {
        node.layer->backward(in, act_[ii], g, nullptr);
      } else if (!has_grad[static_cast<std::size_t>(j)]) {
        node.layer->backward(in, act_[ii], g, &grad_[static_cast<std::size_t>(j)]);
        has_grad[static_cast<std::size_t>(j)] = 1;
      } else {
        node.layer->backward(in, act_[ii], g, &scratch_);
        grad_[static_cast<std::size_t>(j)].flat() += scratch_.flat();
      }
      continue;
    }
    node.layer->backward(in, act_[ii], g, &dcat_);
    std::vector<Tensor*> gs;
    bool acc[64];
    if (node.inputs.size() > 64) throw InvalidArgument("Network: more than 64 concatenated inputs");
    for (std::size_t k = 0; k < node.inputs.size(); ++k) {
      const int j = node.inputs[k];
      if (j < 0) {
        dummy_.resize(x.shape());
        gs.push_back(&dummy_);
        acc[k] = false;
        continue;
      }
      Tensor& gj = grad_[static_cast<std::size_t>(j)];
      if (!has_grad[static_cast<std::size_t>(j)]) gj.resize(act_[static_cast<std::size_t>(j)].shape());
      gs.push_back(&gj);
      acc[k] = has_grad[static_cast<std::size_t>(j)] != 0;
      has_grad[static_cast<std::size_t>(j)] = 1;
    }
    split_channels(dcat_, gs, std::span<const bool>(acc, node.inputs.size()));
  }
}

void Network::set_input_size(int h, int w) {
  if (h == in_.h && w == in_.w) return;
  const std::string where = "arch '" + arch_.name + "' on a " + std::to_string(h) + " x " + std::to_string(w) + " input";
  Network other = [&] {
    try {
      return Network(arch_, Shape{1, in_.c, h, w});
    } catch (const ConfigError& e) {
      throw ConfigError(where + ": " + e.what());
    }
  }();
  std::vector<ParamRef> mine = parameters(), theirs = other.parameters();
  // Same arch, so the same parameter names in the same order; only their shapes can differ.
  for (std::size_t k = 0; k < mine.size(); ++k) {
    if (mine[k].value->shape() != theirs[k].value->shape())
      throw ConfigError(where + ": parameter '" + mine[k].name + "' is " + mine[k].value->shape().str() + ", needs " +
                        theirs[k].value->shape().str() + " (a size-dependent layer: the arch is not fully convolutional)");
    *theirs[k].value = *mine[k].value;
  }
  *this = std::move(other);
}

std::vector<ParamRef> Network::parameters() {
  std::vector<ParamRef> all;
  for (std::size_t i = 0; i < nodes_.size(); ++i)
    for (ParamRef p : nodes_[i].layer->parameters()) {
      p.name = arch_.layers[i].name + "/" + p.name;
      all.push_back(std::move(p));
    }
  return all;
}

std::size_t Network::parameter_count() {
  std::size_t n = 0;
  for (const ParamRef& p : parameters()) n += p.value->size();
  return n;
}

void Network::initialize(const Initializer& init, Rng& rng) {
  for (Node& node : nodes_) node.layer->initialize(init, rng);
}

void Network::set_rng(Rng* rng) {
  for (Node& node : nodes_)
    if (auto* d = dynamic_cast<Dropout*>(node.layer.get())) d->set_rng(rng);
}

void Network::set_batch_window(int offset, int total) {
  for (Node& node : nodes_)
    if (auto* d = dynamic_cast<Dropout*>(node.layer.get())) d->set_batch_window(offset, total);
}

std::string Network::summary() {
  std::ostringstream os;
  os << "arch '" << arch_.name << "', input " << in_.c << "x" << in_.h << "x" << in_.w << "\n";
  for (std::size_t i = 0; i < nodes_.size(); ++i) {
    const Node& n = nodes_[i];
    os << "  " << arch_.layers[i].name << ": " << n.layer->describe() << "  <- ";
    for (std::size_t k = 0; k < n.inputs.size(); ++k)
      os << (k ? " + " : "") << (n.inputs[k] < 0 ? "input" : arch_.layers[static_cast<std::size_t>(n.inputs[k])].name);
    os << "  -> " << n.out.c << "x" << n.out.h << "x" << n.out.w << "  (" << n.layer->parameter_count()
       << " params)\n";
  }
  os << "  total parameters: " << parameter_count() << "\n";
  return os.str();
}

}  // namespace dc
