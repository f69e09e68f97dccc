#include "dc/learning/feature_channels.hpp"

#include <algorithm>

#include "dc/core/error.hpp"
#include "dc/sph/sph_setting.hpp"

namespace dc {

namespace {

constexpr FeatureChannel kAllChannels[] = {FeatureChannel::Mass,  FeatureChannel::Vx,
                                           FeatureChannel::Vy,    FeatureChannel::Omega,
                                           FeatureChannel::ContactDensity, FeatureChannel::Nx,
                                           FeatureChannel::Ny,    FeatureChannel::LambdaPrevN,
                                           FeatureChannel::LambdaPrevT, FeatureChannel::VrelN,
                                           FeatureChannel::VrelT, FeatureChannel::Gap,
                                           FeatureChannel::Coverage, FeatureChannel::OrientC,
                                           FeatureChannel::OrientS, FeatureChannel::WPrevN,
                                           FeatureChannel::WPrevT};

SphTransferDef normalised_label_def(SphTransferDef d) {
  d.grid.channels = kLabelChannelCount;
  d.normalisation = SphNormalisation::Shepard;
  return d;
}

bool uses_w_prev(std::span<const FeatureChannel> cs) {
  return std::any_of(cs.begin(), cs.end(),
                     [](FeatureChannel c) { return c == FeatureChannel::WPrevN || c == FeatureChannel::WPrevT; });
}

}  // namespace

const char* to_string(FeatureChannel c) {
  switch (c) {
    case FeatureChannel::Mass: return "mass";
    case FeatureChannel::Vx: return "vx";
    case FeatureChannel::Vy: return "vy";
    case FeatureChannel::Omega: return "omega";
    case FeatureChannel::ContactDensity: return "contact_density";
    case FeatureChannel::Nx: return "nx";
    case FeatureChannel::Ny: return "ny";
    case FeatureChannel::LambdaPrevN: return "lambda_prev_n";
    case FeatureChannel::LambdaPrevT: return "lambda_prev_t";
    case FeatureChannel::VrelN: return "vrel_n";
    case FeatureChannel::VrelT: return "vrel_t";
    case FeatureChannel::Gap: return "gap";
    case FeatureChannel::Coverage: return "coverage";
    case FeatureChannel::OrientC: return "orient_c";
    case FeatureChannel::OrientS: return "orient_s";
    case FeatureChannel::WPrevN: return "w_prev_n";
    case FeatureChannel::WPrevT: return "w_prev_t";
  }
  return "?";
}

FeatureChannel parse_feature_channel(std::string_view name) {
  for (FeatureChannel c : kAllChannels)
    if (name == to_string(c)) return c;
  std::string valid;
  for (FeatureChannel c : kAllChannels) valid += std::string(valid.empty() ? "" : ", ") + to_string(c);
  throw ConfigError("unknown feature channel '" + std::string(name) + "' (valid: " + valid + ")");
}

std::vector<FeatureChannel> parse_feature_channels(const std::string& list) {
  std::vector<FeatureChannel> out;
  std::size_t start = 0;
  while (start <= list.size()) {
    const std::size_t comma = std::min(list.find(',', start), list.size());
    std::string item = list.substr(start, comma - start);
    const auto b = item.find_first_not_of(" \t"), e = item.find_last_not_of(" \t");
    if (b == std::string::npos) throw ConfigError("feature channels '" + list + "': empty item");
    const FeatureChannel c = parse_feature_channel(item.substr(b, e - b + 1));
    if (std::find(out.begin(), out.end(), c) != out.end())
      throw ConfigError("feature channels '" + list + "': '" + to_string(c) + "' listed twice");
    out.push_back(c);
    start = comma + 1;
  }
  return out;
}

std::vector<std::string> feature_channel_names(std::span<const FeatureChannel> channels) {
  std::vector<std::string> out;
  for (FeatureChannel c : channels) out.emplace_back(to_string(c));
  return out;
}

std::vector<FeatureChannel> default_feature_channels() {
  return {FeatureChannel::Mass, FeatureChannel::Vx, FeatureChannel::Vy, FeatureChannel::Omega,
          FeatureChannel::ContactDensity};
}

std::vector<FeatureChannel> residual_feature_channels() {
  return {FeatureChannel::Mass,        FeatureChannel::Vx,          FeatureChannel::Vy,
          FeatureChannel::Omega,       FeatureChannel::ContactDensity, FeatureChannel::LambdaPrevN,
          FeatureChannel::LambdaPrevT, FeatureChannel::VrelN,       FeatureChannel::VrelT,
          FeatureChannel::Gap};
}

std::vector<FeatureChannel> residual_w_feature_channels() {
  std::vector<FeatureChannel> out = residual_feature_channels();
  out.push_back(FeatureChannel::WPrevN);
  out.push_back(FeatureChannel::WPrevT);
  return out;
}

bool needs_lcp_problem(std::span<const FeatureChannel> channels) { return uses_w_prev(channels); }

std::vector<std::string> label_channel_names() { return {"lambda_n", "lambda_t"}; }

FeatureImageDef FeatureImageDef::for_box(double width, double height) {
  FeatureImageDef d;
  d.sph = default_sph_setting(width, height);
  return d;
}

void FeatureImageDef::validate() const {
  try {
    normalised_label_def(sph).validate();
  } catch (const std::exception& e) {
    throw ConfigError(std::string("feature image grid: ") + e.what());
  }
  if (channels.empty()) throw ConfigError("feature image: no feature channels");
  for (std::size_t a = 0; a < channels.size(); ++a)
    for (std::size_t b = a + 1; b < channels.size(); ++b)
      if (channels[a] == channels[b])
        throw ConfigError(std::string("feature image: channel '") + to_string(channels[a]) + "' listed twice");
}

}  // namespace dc
