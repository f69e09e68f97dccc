#pragma once
// `deepcontact train` across MPI ranks (docs/cluster.md): data-parallel SGD via
// the Trainer's DataParallelGroup hook (dc/learning/data_parallel.hpp), implemented here
// with MPI_Allreduce over world(). Every rank loads the data set and trains the same model;
// rank 0 alone writes OUT, OUT.ckpt and the loss files and prints.
#include <cstdint>

#include "cluster/comm.hpp"
#include "dc/learning/data_parallel.hpp"
#include "dc/learning/model.hpp"

namespace dc::cli {

class CommGroup final : public DataParallelGroup {
 public:
  explicit CommGroup(const Comm& comm) : comm_(comm) {}
  [[nodiscard]] int rank() const override { return comm_.rank(); }
  [[nodiscard]] int size() const override { return comm_.size(); }
  void sum(std::span<double> values) const override { comm_.sum(values); }

 private:
  const Comm& comm_;
};

/// True on every rank when `local` is true on any (a collective: stop decisions must agree).
bool any_rank(const Comm& comm, bool local);

/// FNV-1a of every weight's bytes (identical weights ⇔ identical hashes, practically).
std::uint64_t weights_hash(Model& model);

/// IoError unless every rank holds the same weights (a collective; cheap).
void require_identical_weights(const Comm& comm, Model& model);

}  // namespace dc::cli
