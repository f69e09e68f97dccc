#pragma once
// Morton (Z-order) numbering of points over a uniform grid: the order `[bodies] order =
// "morton"` gives the generated bodies, so that bodies close in space get close indices and
// the per-body arrays, J's columns and the contact rows (sorted by body key) are walked with
// locality once the scene outgrows the caches (docs/engine.md "Step cost against size").
#include <cstdint>
#include <span>
#include <vector>

#include "dc/core/vec2.hpp"

namespace dc {

/// Indices of `centres` sorted by the Morton code of their cell (side `cell` [m], cells
/// counted from the smallest x and y present; x in the even bits, y in the odd ones, 32 bits
/// each), ties by index: a permutation, deterministic (integer keys only). Throws
/// InvalidArgument when `cell` is not finite and > 0.
std::vector<int> morton_order(std::span<const Vec2> centres, double cell);

/// The Morton code of cell (i, j): the bits of i and j interleaved (bit k of i → bit 2k,
/// bit k of j → bit 2k + 1).
std::uint64_t morton_code(std::uint32_t i, std::uint32_t j);

}  // namespace dc
