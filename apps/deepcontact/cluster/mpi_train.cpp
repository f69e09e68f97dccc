// Helpers of data-parallel training across ranks (mpi_train.hpp).
#include "cluster/mpi_train.hpp"

#include <cstring>
#include <string>

#include "dc/core/error.hpp"

namespace dc::cli {

bool any_rank(const Comm& comm, bool local) {
  std::int64_t v = local ? 1 : 0;
  comm.max(std::span<std::int64_t>(&v, 1));
  return v != 0;
}

std::uint64_t weights_hash(Model& model) {
  std::uint64_t h = 1469598103934665603ULL;
  for (const ParamRef& p : model.network().parameters()) {
    const auto* b = reinterpret_cast<const unsigned char*>(p.value->data());
    for (std::size_t i = 0; i < p.value->size() * sizeof(float); ++i) h = (h ^ b[i]) * 1099511628211ULL;
  }
  return h;
}

void require_identical_weights(const Comm& comm, Model& model) {
  if (!comm.parallel()) return;
  const auto h = static_cast<std::int64_t>(weights_hash(model));
  std::int64_t lo = h, hi = h;
  comm.min(std::span<std::int64_t>(&lo, 1));
  comm.max(std::span<std::int64_t>(&hi, 1));
  if (lo != hi) throw IoError("train: the ranks' weights differ after training (data-parallel reduction not identical)");
}

}  // namespace dc::cli
