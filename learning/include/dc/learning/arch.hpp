#pragma once
// Architecture description: the text form of a Network, stored verbatim in model files and
// accepted by `train --arch FILE`. TOML: a `name` plus an ordered array of [[layer]] tables
// (name, type = conv | relu | dropout | dense | upsample, input = node or list → channel concat,
// default the previous layer; conv: out, kernel (odd, 3), stride (1), relu; dropout: rate;
// dense: out = N or [C, H, W]; upsample: match = "node" or size = [H, W], default 2H×2W).
// Each layer is one graph node and may only read nodes defined earlier in the file; the last
// is the network output. Shapes are resolved when a Network is built for a concrete input
// (C, H, W), so one arch serves any channel count and grid size (docs/learning.md "Networks
// and the arch format").
#include <array>
#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

namespace dc {

/// One [[layer]] entry. Fields not used by a type keep their defaults.
struct LayerSpec {
  std::string name;
  std::string type;                 ///< conv | relu | dropout | dense | upsample
  std::vector<std::string> inputs;  ///< empty = previous layer; ≥ 2 = channel concat
  int out = 0;                      ///< conv: channels; dense: features (if out_shape empty)
  std::vector<int> out_shape;       ///< dense: [C, H, W] output sample shape
  int kernel = 3;                   ///< conv
  int stride = 1;                   ///< conv
  bool relu = false;                ///< conv, dense
  double rate = 0.0;                ///< dropout
  std::string match;                ///< upsample: copy H×W of this node
  std::array<int, 2> size{0, 0};    ///< upsample: explicit output H×W (0 = 2×)
};

struct ArchSpec {
  std::string name;
  std::vector<LayerSpec> layers;

  /// Parse the TOML text; `source` names the file in messages. Throws ConfigError with a
  /// one-line message naming the layer and key (unknown type or key, wrong value type,
  /// duplicate or unknown node name, missing required key).
  static ArchSpec parse(std::string_view text, std::string_view source = "<arch>");
  /// Read and parse a file; throws IoError if it cannot be read, ConfigError if invalid.
  static ArchSpec load(const std::filesystem::path& path);
  /// Canonical TOML text; parse(to_toml()) reproduces the spec.
  [[nodiscard]] std::string to_toml() const;
};

/// The default small U-Net (≈ 40 k weights for 4 input channels, 2 outputs):
///   e1 conv→16 s1 relu [H]      e2 conv→32 s2 relu [⌈H/2⌉]   e3 conv→32 s2 relu [⌈H/4⌉]
///   drop dropout 0.1 → u2 upsample(match e2) → d2 conv([u2,e2])→32 relu
///   u1 upsample(match e1) → d1 conv([u1,e1])→16 relu → out conv→out_channels (linear)
ArchSpec default_arch(int out_channels = 2, double dropout = 0.1);

/// The dense-head network ("seed-dense"): conv→32 s2 relu, conv→32 s2 relu, dropout, dense to
/// [out_channels, out_h, out_w]. For 61 × 61 that is 32·16·16 = 8192 → 7442 outputs,
/// ≈ 61 M weights.
ArchSpec seed_dense_arch(int out_channels = 2, int out_h = 61, int out_w = 61, double dropout = 0.1);

/// True for the names of the built-in architectures: "" and "default" (default_arch),
/// "seed-dense" (seed_dense_arch).
bool is_builtin_arch(const std::string& name);
/// The architecture `deepcontact train --arch` names: a built-in one (with `out_channels`,
/// the output size for seed-dense, and `dropout`) or an existing TOML file (ArchSpec::load,
/// which states its own dropout). ConfigError for anything else.
ArchSpec select_arch(const std::string& name_or_file, int out_channels, int out_h, int out_w, double dropout);

}  // namespace dc
