#pragma once
// Whether a world steps its bodies in the engine-internal Morton order (`[bodies]
// internal_order`, world_def.hpp; docs/engine.md "Spatial body order").
#include "dc/engine/body_state.hpp"
#include "dc/engine/world_def.hpp"

namespace dc {

/// "morton": always (InternalBodyOrder rejects shapes); "none": never; "auto": when the world
/// starts with at least internal_order_auto_min_bodies bodies, all dynamic circles (no shape
/// table). Decided once, at construction, on the bodies the world starts with.
[[nodiscard]] inline bool steps_in_internal_order(InternalOrder order, const BodyState& initial) {
  switch (order) {
    case InternalOrder::Morton: return true;
    case InternalOrder::Auto:
      return initial.shapes.empty() && initial.size() >= static_cast<std::size_t>(internal_order_auto_min_bodies);
    case InternalOrder::None: break;
  }
  return false;
}

}  // namespace dc
