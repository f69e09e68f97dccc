// Comm over MPI (DC_HAVE_MPI) or serial (comm.hpp).
#include "cluster/comm.hpp"

#include <chrono>
#include <cstdio>
#include <thread>
#include <cstdlib>
#include <limits>
#include <string>

#include "dc/core/error.hpp"

#ifdef DC_HAVE_MPI
// The C API only: OpenMPI's and MPICH's deprecated C++ bindings would need libmpi_cxx.
#define OMPI_SKIP_MPICXX 1
#define MPICH_SKIP_MPICXX 1
#include <mpi.h>
#endif

namespace dc::cli {
namespace {

Comm& world_mutable() {
  static Comm comm;  // the process's one communicator (MPI's world is process-global too)
  return comm;
}

[[maybe_unused]] int checked_count(std::size_t n) {
  if (n > static_cast<std::size_t>(std::numeric_limits<int>::max()))
    throw IoError("MPI message of " + std::to_string(n) + " bytes exceeds 2 GiB");
  return static_cast<int>(n);
}

bool launched_by_mpi() {
  for (const char* v : {"OMPI_COMM_WORLD_SIZE", "PMIX_RANK", "PMI_SIZE", "PMI_RANK"})
    if (std::getenv(v) != nullptr) return true;
  return false;
}

}  // namespace

const Comm& world() { return world_mutable(); }

std::pair<std::size_t, std::size_t> block_of(std::size_t n, int rank, int size) {
  const std::size_t r = static_cast<std::size_t>(rank), k = static_cast<std::size_t>(size);
  const std::size_t base = n / k, extra = n % k;
  const std::size_t begin = r * base + std::min(r, extra);
  return {begin, begin + base + (r < extra ? 1 : 0)};
}

#ifdef DC_HAVE_MPI

MpiSession::MpiSession(int& argc, char**& argv) {
  if (!launched_by_mpi()) return;
  int provided = 0;
  MPI_Init_thread(&argc, &argv, MPI_THREAD_FUNNELED, &provided);
  initialised_ = true;
  Comm& c = world_mutable();
  MPI_Comm_rank(MPI_COMM_WORLD, &c.rank_);
  MPI_Comm_size(MPI_COMM_WORLD, &c.size_);
}

MpiSession::~MpiSession() {
  if (!initialised_) return;
  // MPI_Finalize waits for the slowest rank in a busy loop; while rank 0 writes a report
  // the others would burn a core each and slow it down. Wait sleeping first.
  world().barrier();
  MPI_Finalize();
}

void Comm::barrier() const {
  if (!parallel()) return;
  MPI_Request request;
  MPI_Ibarrier(MPI_COMM_WORLD, &request);
  for (int done = 0;;) {
    MPI_Test(&request, &done, MPI_STATUS_IGNORE);
    if (done) break;
    std::this_thread::sleep_for(std::chrono::microseconds(500));
  }
}

void Comm::broadcast(Bytes& data, int root) const {
  if (!parallel()) return;
  unsigned long long n = data.size();
  MPI_Bcast(&n, 1, MPI_UNSIGNED_LONG_LONG, root, MPI_COMM_WORLD);
  data.resize(static_cast<std::size_t>(n));
  MPI_Bcast(data.data(), checked_count(data.size()), MPI_BYTE, root, MPI_COMM_WORLD);
}

std::vector<Bytes> Comm::gather(const Bytes& mine, int root) const {
  if (!parallel()) return {mine};
  const int n = checked_count(mine.size());
  std::vector<int> counts(rank_ == root ? static_cast<std::size_t>(size_) : 0), displs;
  MPI_Gather(&n, 1, MPI_INT, counts.data(), 1, MPI_INT, root, MPI_COMM_WORLD);
  Bytes all;
  if (rank_ == root) {
    std::size_t total = 0;
    for (int c : counts) {
      displs.push_back(checked_count(total));
      total += static_cast<std::size_t>(c);
    }
    checked_count(total);
    all.resize(total);
  }
  MPI_Gatherv(mine.data(), n, MPI_BYTE, all.data(), counts.data(), displs.data(), MPI_BYTE, root, MPI_COMM_WORLD);
  std::vector<Bytes> out;
  if (rank_ == root)
    for (int r = 0; r < size_; ++r) {
      const auto b = all.begin() + displs[static_cast<std::size_t>(r)];
      out.emplace_back(b, b + counts[static_cast<std::size_t>(r)]);
    }
  return out;
}

// Point-to-point waits (and barrier) poll with a short sleep instead of MPI's busy wait: the waiting
// thread (generate's writer) shares its rank's cores with that rank's simulation workers,
// and a busy wait would take a core from them (docs/cluster.md).
static void idle_wait() { std::this_thread::sleep_for(std::chrono::microseconds(500)); }

void Comm::send(const Bytes& data, int dest, int tag) const {
  if (!parallel()) throw InvalidArgument("Comm::send: no other rank");
  MPI_Request request;
  MPI_Isend(data.data(), checked_count(data.size()), MPI_BYTE, dest, tag, MPI_COMM_WORLD, &request);
  for (int done = 0;;) {
    MPI_Test(&request, &done, MPI_STATUS_IGNORE);
    if (done) break;
    idle_wait();
  }
}

Bytes Comm::receive(int source, int tag) const {
  if (!parallel()) throw InvalidArgument("Comm::receive: no other rank");
  MPI_Status status;
  for (int found = 0;;) {
    MPI_Iprobe(source, tag, MPI_COMM_WORLD, &found, &status);
    if (found) break;
    idle_wait();
  }
  int n = 0;
  MPI_Get_count(&status, MPI_BYTE, &n);
  Bytes data(static_cast<std::size_t>(n));
  MPI_Recv(data.data(), n, MPI_BYTE, source, tag, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
  return data;
}

bool Comm::has_message(int source, int tag) const {
  if (!parallel()) return false;
  int found = 0;
  MPI_Iprobe(source, tag, MPI_COMM_WORLD, &found, MPI_STATUS_IGNORE);
  return found != 0;
}

void Comm::sum(std::span<double> v) const {
  if (parallel()) MPI_Allreduce(MPI_IN_PLACE, v.data(), checked_count(v.size()), MPI_DOUBLE, MPI_SUM, MPI_COMM_WORLD);
}

void Comm::min(std::span<std::int64_t> v) const {
  if (parallel()) MPI_Allreduce(MPI_IN_PLACE, v.data(), checked_count(v.size()), MPI_INT64_T, MPI_MIN, MPI_COMM_WORLD);
}

void Comm::max(std::span<std::int64_t> v) const {
  if (parallel()) MPI_Allreduce(MPI_IN_PLACE, v.data(), checked_count(v.size()), MPI_INT64_T, MPI_MAX, MPI_COMM_WORLD);
}

void Comm::abort(int code) const {
  std::fflush(stdout);
  std::fflush(stderr);
  if (parallel()) MPI_Abort(MPI_COMM_WORLD, code);
  std::exit(code);
}

#else  // serial build: no MPI found by CMake

MpiSession::MpiSession(int&, char**&) {
  if (launched_by_mpi())
    std::fprintf(stderr, "deepcontact: warning: started by an MPI launcher, but this build has no MPI; "
                         "every rank runs the whole command alone\n");
}
MpiSession::~MpiSession() = default;
void Comm::barrier() const {}
void Comm::broadcast(Bytes&, int) const {}
std::vector<Bytes> Comm::gather(const Bytes& mine, int) const { return {mine}; }
void Comm::send(const Bytes&, int, int) const { throw InvalidArgument("Comm::send: no other rank"); }
Bytes Comm::receive(int, int) const { throw InvalidArgument("Comm::receive: no other rank"); }
bool Comm::has_message(int, int) const { return false; }
void Comm::sum(std::span<double>) const {}
void Comm::min(std::span<std::int64_t>) const {}
void Comm::max(std::span<std::int64_t>) const {}
void Comm::abort(int code) const {
  std::fflush(stdout);
  std::fflush(stderr);
  std::exit(code);
}

#endif

}  // namespace dc::cli
