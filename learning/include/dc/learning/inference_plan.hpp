#pragma once
// InferencePlan: a compiled, forward-only evaluation of a Network for one sample on one
// thread — what the cnn warm starter runs every step. Weights packed and buffers allocated
// once; each conv's input gathered into the direct kernel's padded rows with concatenation,
// upsampling and standardisation folded in; convs evaluated only at the output rows the
// requested pixels depend on, template rows copied (docs/learning.md "The fused inference plan").
// Contract: the float operations per output element are those of Model::network_output_at
// (same bits). Fused when the build has the AVX-512 direct kernels and the graph is conv and
// upsample nodes (last node a conv, outputs ≤ 64 wide, stride 1 or 3 × 3 stride 2); otherwise
// run() standardises a copy and calls Network::forward_at, with the same results.
// Rebuild a plan after changing the network's weights, the statistics or the input size (a
// fused plan copies them when built). `net` must outlive the plan.
#include <span>
#include <string>
#include <utility>
#include <vector>

#include "dc/learning/channel_stats.hpp"
#include "dc/learning/network.hpp"
#include "dc/learning/tensor.hpp"

namespace dc {

class Conv2d;

class InferencePlan {
 public:
  /// Compiles `net` at its current input size with the input standardisation `input_stats`
  /// (one entry per input channel; throws InvalidArgument otherwise).
  InferencePlan(Network& net, const ChannelStats& input_stats);

  InferencePlan(const InferencePlan&) = delete;
  InferencePlan& operator=(const InferencePlan&) = delete;
  InferencePlan(InferencePlan&&) noexcept = default;
  InferencePlan& operator=(InferencePlan&&) noexcept = default;

  /// The network's output for raw (unstandardised) features [1, C, H, W] at the listed output
  /// pixels (indices y·W + x; throws InvalidArgument for one outside the output): equal to
  /// Model::network_output_at there; other pixels are unspecified. The reference stays valid
  /// until the next call. `step_ms` (optional, profiling) receives the calling thread's CPU
  /// milliseconds per step (see step_name), resized to step_count().
  const Tensor& run(const Tensor& features, std::span<const int> pixels, std::vector<double>* step_ms = nullptr);

  /// Input rows [lo, hi] (y, inclusive; empty when lo > hi) outside which every raw feature
  /// of every channel is +0 (bit pattern 0).
  struct InputRows {
    int lo = 0, hi = -1;
  };
  /// run() when the caller knows where the features are nonzero (FeatureImageBuilder::
  /// nonzero_rows() after its features()): the rows outside `rows` are taken as empty and
  /// those inside as not empty, without scanning the image — the same values at the pixels
  /// (an empty row inside `rows` is computed instead of copied from the template row, with
  /// the same bits). The caller guarantees the +0; a wrong range gives wrong values.
  const Tensor& run(const Tensor& features, std::span<const int> pixels, InputRows rows,
                    std::vector<double>* step_ms = nullptr);

  /// True when the fused path runs (see the header comment), false for the unfused one.
  [[nodiscard]] bool fused() const { return !steps_.empty(); }
  /// Steps of run(): one per materialised conv node (its gather included) and the sparse
  /// head; a single "network" step when not fused.
  [[nodiscard]] std::size_t step_count() const { return fused() ? steps_.size() : 1; }
  /// Name of step i: the conv node's name ("e1", ..., "out"), or "network".
  [[nodiscard]] std::string step_name(std::size_t i) const;
  /// True when this plan was compiled from `net` (the object, not its weights).
  [[nodiscard]] bool built_for(const Network& net) const { return net_ == &net; }

  /// One 16-lane vector of a padded row's gather: input columns ix0 … ix0 + 15, their
  /// valid lanes (inside [0, w)) and, through a nearest upsampling, the source columns
  /// from sbase with the lane → source index shift (see inference_plan.cpp). An implementation
  /// detail of the gather kernels, public so that they can be free functions.
  struct Columns {
    int ix0 = 0, sbase = 0, shift = 0;
    unsigned valid = 0, up_valid = 0;  ///< lane masks
  };

 private:
  /// One input channel of a fused step: plane `channel` of node `node`'s output (−1 = the
  /// network input, standardised on the fly), read through a nearest 2× upsampling if `up`.
  struct Source {
    int node = -1;      ///< producing node, −1 = network input
    int channel = 0;    ///< channel in that node's output
    int h = 0, w = 0;   ///< that plane's size
    int pitch = 0;      ///< its row pitch in the stored layout (w, or a flat step's Wq)
    long plane = 0;     ///< floats per channel in the stored layout
    bool up = false;    ///< read as out(Y, X) = in(Y/2, X/2)
    bool standardise = false;  ///< network input: (v − mean)·inv
    float mean = 0.0f, inv = 1.0f;
  };
  /// One fused conv node.
  struct Step {
    int node = 0;                 ///< network node index
    int cin = 0, cout = 0, k = 1, stride = 1;
    bool relu = false;
    bool sparse = false;          ///< the 1 × 1 head, at the listed pixels only
    int h = 0, w = 0, ho = 0, wo = 0;  ///< (virtual) input and output size
    int pad_top = 0, pad_left = 0;
    bool flat = false;            ///< direct_flat (small outputs) instead of direct_tile
    int rows = 0, pitch = 0;      ///< padded rows R and row pitch Wp of the kernel's buffer
    long x_plane = 0;             ///< floats per input channel in the kernel's buffer
    std::vector<int> off;         ///< flat: offset of each tap (ky·k + kx) in a channel's buffer
    std::vector<Columns> cols;    ///< the gather's source vectors of one padded row, in order
    std::vector<Source> src;      ///< cin entries, in concatenation order
    std::vector<float> weight;    ///< packed for the kernel (dense) or [cout][cin] (sparse)
    std::vector<float> bias;      ///< cout entries
    std::vector<std::pair<int, bool>> inputs;  ///< distinct (node, up) of src: what the rows read
    bool has_template = false;    ///< rows-layout output rows may be template rows
    std::vector<float> tmpl;      ///< the template row, [cout][wo]
  };

  bool compile(Network& net);
  bool add_step(Network& net, std::size_t i, const std::vector<char>& conv, bool plain_layout);
  void layout_dense(Step& s, Conv2d& layer, bool plain_layout);
  void run_dense(const Step& s, const Tensor& x);
  void gather_rows(const Step& s, const Tensor& x, int pr0, int pr1, float* xp) const;
  // Row bookkeeping (inference_rows.cpp).
  /// Whether output row oy of s reads only template rows (input: empty rows), no padding.
  [[nodiscard]] bool reads_templates(const Step& s, int oy) const;
  /// Template flags (forward, from the input's empty rows), then the rows each step must
  /// compute (backward, from the head's pixels; everything when `all`).
  /// `rows`: the caller's nonzero input rows (run with InputRows), null = scan the input.
  void plan_rows(const Tensor& x, std::span<const int> pixels, bool all, const InputRows* rows);
  const Tensor& run_plan(const Tensor& features, std::span<const int> pixels, const InputRows* rows,
                         std::vector<double>* step_ms);
  /// Runs the plan once on an all-zero input and stores each step's template row.
  void calibrate_templates();
  /// Copies s's template into the output rows that are needed, template, not computed.
  void fill_template_rows(const Step& s);
  void run_sparse(const Step& s, const Tensor& x, std::span<const int> pixels);
  [[nodiscard]] const float* plane(const Source& src, const Tensor& x) const;

  Network* net_;
  ChannelStats stats_;
  Shape in_, out_shape_;
  std::vector<Step> steps_;
  std::vector<Tensor> act_;       ///< per node: output of a materialised conv (others empty)
  std::vector<float> pad_;        ///< the kernel's padded rows, sized for the largest step
  std::vector<float> block_;      ///< the sparse head's block of 16 pixels × its input channels
  std::vector<const float*> bases_;  ///< the sparse head's source planes of this call
  std::vector<int> head_lo_, head_hi_;  ///< per output row: the listed pixels' first and last column
  std::vector<char> mark_;        ///< per output pixel: listed in this call
  Tensor scratch_, out_;
  std::vector<char> empty_in_;                ///< per input row: all raw features +0
  std::vector<std::vector<char>> tmpl_rows_;  ///< per node, per output row: a template row
  std::vector<std::vector<char>> need_rows_;  ///< per node, per output row: read by a later step
  std::vector<std::vector<char>> comp_rows_;  ///< per node, per output row: computed this call
};

}  // namespace dc
