#pragma once
// Data-parallel SGD across processes (docs/learning.md "Threads and determinism",
// docs/cluster.md): the Trainer's hook for summing minibatch gradients over processes, without
// MPI here (apps/deepcontact/cluster/mpi_train.cpp implements it with MPI_Allreduce).
// K > 1 processes hold the whole data set, the same weights and the same random stream; process
// r runs the contiguous shard [b·r/K, b·(r+1)/K) of each minibatch (Dropout::set_batch_window
// draws the whole batch's masks and keeps the shard's), and the group sums (den_r·∇_r, num_r,
// den_r), den_r the shard's MSE denominator, so ∇ = Σ den_r ∇_r / Σ den_r is the whole batch's
// gradient on every process. The validation loss is computed on the whole split everywhere.
// Summation grouping differs from one process (per shard in float, across shards in double):
// weights agree with the one-process run to rounding; for fixed K and thread count a run is
// deterministic. K = 1 is the one-process code path exactly.
#include <span>

namespace dc {

class DataParallelGroup {
 public:
  virtual ~DataParallelGroup() = default;
  [[nodiscard]] virtual int rank() const = 0;  ///< 0 … size − 1
  [[nodiscard]] virtual int size() const = 0;  ///< K
  /// Element-wise sum over all processes, in place; the result is bit-identical on every
  /// process and, for a fixed K, from run to run.
  virtual void sum(std::span<double> values) const = 0;
};

}  // namespace dc
