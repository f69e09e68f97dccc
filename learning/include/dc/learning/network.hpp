#pragma once
// Network: a small directed acyclic graph of layers built from an ArchSpec for a concrete
// input sample shape (C, H, W). Node i runs layer i on the output of its input node, or on
// the channel concatenation of several input nodes (skip connections); the last node is
// the output. The graph owns all activations and their gradients, so layers never copy
// them (see layer.hpp), and buffers are reused across calls of equal batch size.
//
// Backward walks the nodes in reverse; a node output read by several consumers (e.g. an
// encoder feature map feeding both the next conv and a skip concat) sums their
// gradients in consumer order. The input gradient of the network is not computed.
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "dc/learning/arch.hpp"
#include "dc/learning/layers/layer.hpp"

namespace dc {

class Initializer;
class Rng;

class Network {
 public:
  /// Build for input samples of shape [·, in.c, in.h, in.w]. Throws ConfigError when the
  /// arch does not fit the input (channel/size mismatch, bad upsample target, ...).
  Network(ArchSpec arch, const Shape& in);

  Network(const Network&) = delete;
  Network& operator=(const Network&) = delete;
  Network(Network&&) noexcept = default;
  Network& operator=(Network&&) noexcept = default;

  /// Forward a batch [N, C, H, W]; the returned reference stays valid until the next call.
  /// `node_ms` (optional, for profiling) receives the CPU milliseconds of the calling thread
  /// in each node (its concatenation included; a one-thread figure), resized to size().
  const Tensor& forward(const Tensor& x, bool training, std::vector<double>* node_ms = nullptr);
  /// Inference of one sample [1, C, H, W] at selected output pixels only (indices y·W + x of
  /// the output plane; the cnn starter reads the contacts' stencil nodes). When the last node is a 1 × 1,
  /// stride-1 conv, it and the nearest upsamplings read by it alone are evaluated at
  /// `pixels` only (a "per-node head" at full resolution costs no full-resolution buffers);
  /// every other node runs as in forward(). Otherwise this is forward(). `out` is resized to
  /// the output shape; the listed pixels hold forward()'s values (same float operations; the
  /// AVX-512 build gives the same bits, the portable GEMM path may differ in the last bits),
  /// the others are unspecified. Returns true when the sparse path ran.
  bool forward_at(const Tensor& x, std::span<const int> pixels, Tensor& out);
  /// Backward from dL/dy of the last forward; overwrites every parameter gradient.
  void backward(const Tensor& dy);

  /// Re-targets the network to input samples [·, in.c, h, w] of another height and width
  /// (same channels): the graph is rebuilt from the arch for the new size (every `match`
  /// upsampling takes its new target's size) and each parameter is carried over by name,
  /// so a fully convolutional net (conv, relu, dropout, matched upsampling) runs on any
  /// grid with the weights it was trained with. A no-op when the size is unchanged (the
  /// network is then untouched, bit for bit). Throws ConfigError naming the arch, the size
  /// and the layer when it cannot run there: a parameter whose shape depends on the input
  /// size (dense) or a layer that does not fit it (an explicit upsample size). Dropout
  /// layers lose their set_rng / set_batch_window bindings (rebind them before training).
  void set_input_size(int h, int w);

  /// All parameters, named "<node>/weight" etc., in node order (stable: the model file
  /// and the optimiser rely on it).
  std::vector<ParamRef> parameters();
  [[nodiscard]] std::size_t parameter_count();
  /// Draw all weights with `init` from rng, in node order; biases zero.
  void initialize(const Initializer& init, Rng& rng);
  /// Bind the random stream used by every dropout layer in training (null unbinds).
  void set_rng(Rng* rng);
  /// Dropout::set_batch_window on every dropout layer (data-parallel training).
  void set_batch_window(int offset, int total);

  [[nodiscard]] const ArchSpec& arch() const { return arch_; }
  [[nodiscard]] Shape input_shape() const { return in_; }    ///< n = 1
  [[nodiscard]] Shape output_shape() const { return out_; }  ///< n = 1
  [[nodiscard]] std::size_t size() const { return nodes_.size(); }
  [[nodiscard]] Layer& layer(std::size_t i) { return *nodes_.at(i).layer; }
  [[nodiscard]] const std::string& node_name(std::size_t i) const { return arch_.layers.at(i).name; }
  /// Node i's input nodes (−1 = the network input; several = their channel concatenation).
  [[nodiscard]] const std::vector<int>& node_inputs(std::size_t i) const { return nodes_.at(i).inputs; }
  /// Node i's output sample shape (n = 1).
  [[nodiscard]] Shape node_shape(std::size_t i) const { return nodes_.at(i).out; }
  /// One line per node: name, layer, input(s), output shape, parameter count.
  [[nodiscard]] std::string summary();

 private:
  struct Node {
    std::unique_ptr<Layer> layer;
    std::vector<int> inputs;  ///< node indices; −1 = network input
    Shape out;                ///< sample shape (n = 1)
  };
  const Tensor& input_of(std::size_t i, const Tensor& x);

  ArchSpec arch_;
  Shape in_, out_;
  std::vector<Node> nodes_;
  std::vector<Tensor> act_, grad_, cat_;  ///< per node: output, dL/doutput, concat input
  Tensor dcat_, scratch_, dummy_;
  const Tensor* last_x_ = nullptr;  ///< input of the last forward (for backward)
};

}  // namespace dc
