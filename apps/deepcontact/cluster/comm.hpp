#pragma once
// dc::cli::Comm: the few collective operations the commands need across MPI ranks
// (docs/cluster.md), behind an interface without MPI headers. MpiSession (one, in main())
// initialises MPI only when a launcher started the process (OMPI_COMM_WORLD_SIZE, PMIX_RANK,
// PMI_SIZE set) and the build found MPI; otherwise world() is the serial communicator and every
// operation a local no-op. Messages are byte buffers (byte_buffer.hpp); reductions are
// element-wise sums in a fixed order for a fixed rank count. MPI_THREAD_FUNNELED: only the main
// thread calls Comm. barrier, send and receive sleep between polls (a waiting rank leaves its
// cores to the work); broadcast, gather, sum, min, max are MPI's blocking collectives.
#include <cstdint>
#include <optional>
#include <span>
#include <vector>

namespace dc::cli {

using Bytes = std::vector<std::uint8_t>;

class Comm {
 public:
  /// The serial communicator: rank 0 of 1.
  Comm() = default;
  [[nodiscard]] int rank() const { return rank_; }
  [[nodiscard]] int size() const { return size_; }
  [[nodiscard]] bool is_root() const { return rank_ == 0; }
  /// True when MPI is initialised and there is more than one rank.
  [[nodiscard]] bool parallel() const { return size_ > 1; }

  /// Waits for every rank, sleeping between polls (no busy wait).
  void barrier() const;
  /// Root's `data` to every rank (resized on the others).
  void broadcast(Bytes& data, int root = 0) const;
  /// Every rank's buffer at `root` (indexed by rank); empty on the other ranks.
  [[nodiscard]] std::vector<Bytes> gather(const Bytes& mine, int root = 0) const;
  /// Point-to-point (blocking; a large message waits until the receiver asks for it).
  void send(const Bytes& data, int dest, int tag) const;
  [[nodiscard]] Bytes receive(int source, int tag) const;
  /// A message from `source` with `tag` is waiting (receive would not block).
  [[nodiscard]] bool has_message(int source, int tag) const;
  /// Element-wise sum over all ranks, in place; the same result on every rank.
  void sum(std::span<double> values) const;
  /// Element-wise minimum / maximum over all ranks, in place.
  void min(std::span<std::int64_t> values) const;
  void max(std::span<std::int64_t> values) const;
  /// Ends every rank of the job with `code` (MPI_Abort); std::exit when serial.
  [[noreturn]] void abort(int code) const;

 private:
  friend class MpiSession;
  int rank_ = 0, size_ = 1;
};

/// MPI_Init_thread / MPI_Finalize around main() (when launched by mpirun/srun; see above).
class MpiSession {
 public:
  MpiSession(int& argc, char**& argv);
  ~MpiSession();
  MpiSession(const MpiSession&) = delete;
  MpiSession& operator=(const MpiSession&) = delete;

 private:
  bool initialised_ = false;
};

/// The world communicator of this process (serial unless an MpiSession initialised MPI).
const Comm& world();

/// [begin, end) of rank r's contiguous block when `n` items are split over `size` ranks
/// (the first n % size ranks get one more).
std::pair<std::size_t, std::size_t> block_of(std::size_t n, int rank, int size);

}  // namespace dc::cli
