#pragma once
// Data-parallel SGD across processes (docs/cluster.md): the Trainer's hook for summing minibatch
// gradients over processes, without any MPI here (apps/deepcontact/cluster/mpi_train.cpp implements it with
// MPI_Allreduce).
//
// With a group of K > 1 processes, every process holds the whole data set, the same
// weights and the same random stream. Each minibatch of b samples is split into K contiguous
// shards ([b·r/K, b·(r+1)/K) for process r); a process runs forward and backward on its
// shard only — the dropout layers draw the masks of the whole batch and keep the shard's
// (Dropout::set_batch_window), so the random stream stays the one-process stream — and the
// group sums (den_r · ∇_r, num_r, den_r) over processes, den_r being the shard's MSE
// denominator: ∇ = Σ den_r ∇_r / Σ den_r is the whole batch's gradient and the same on every
// process, so every process takes the same SGD step. The validation loss is computed
// by every process on the whole validation split (identical everywhere).
//
// What differs from one process: the batch's gradient is summed in another grouping (per
// shard in float, then across shards in double), so weights and losses agree with the
// one-process run to rounding, not bit for bit; for a fixed K and thread count a run is
// deterministic. K = 1 (no group) is the one-process code path exactly.
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
