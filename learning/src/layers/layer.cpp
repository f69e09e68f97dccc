#include "dc/learning/layers/layer.hpp"

namespace dc {

std::size_t Layer::parameter_count() {
  std::size_t total = 0;
  for (const ParamRef& p : parameters()) total += p.value->size();
  return total;
}

}  // namespace dc
