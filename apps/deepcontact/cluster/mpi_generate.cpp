// generate_partition and the simulation messages (mpi_generate.hpp).
#include "cluster/mpi_generate.hpp"

#include <chrono>
#include <string>
#include <thread>

#include "cluster/byte_buffer.hpp"
#include "cluster/sigint_guard.hpp"

namespace dc::cli {
namespace {

constexpr int kTag = 1;  // one tag: messages between two ranks arrive in the order sent (MPI)
constexpr std::int32_t kRecord = 1, kStop = 0;

// Every field, in one order for packing and unpacking. A field added to SimulationRecord
// changes its size: the assertion below then asks to add the field here too.
template <class Io, class Record>
void fields(const Io& io, Record& r) {
  io(r.index);
  io(r.seed);
  io(r.bodies);
  io(r.body_count);
  io(r.max_residual);
  io(r.step);
  io(r.contact_count);
  io(r.residual);
  io(r.features);
  io(r.labels);
  io(r.position);
  io(r.velocity);
  io(r.omega);
  io(r.angle);
  io(r.radius);
  io(r.mass);
  io(r.body_a);
  io(r.body_b);
  io(r.point);
  io(r.normal);
  io(r.gap);
  io(r.lambda_star);
}
static_assert(sizeof(SimulationRecord) == 4 * 8 + 18 * sizeof(std::vector<double>),
              "SimulationRecord changed: add the new field to fields() in mpi_generate.cpp");

}  // namespace

Bytes pack_simulation(const SimulationRecord& rec) {
  ByteWriter w;
  w.put(kRecord);
  fields([&](const auto& v) { w.put(v); }, rec);
  return w.take();
}

std::optional<SimulationRecord> unpack_simulation(const Bytes& message) {
  ByteReader in(message);
  std::int32_t kind = -1;
  in.get(kind);
  if (kind == kStop) return std::nullopt;
  if (kind != kRecord) throw IoError("generate: MPI message of unknown kind " + std::to_string(kind));
  SimulationRecord r;
  fields([&](auto& v) { in.get(v); }, r);
  if (!in.done()) throw IoError("generate: MPI message: trailing bytes");
  return r;
}

void send_generate_stop(const Comm& comm) {
  ByteWriter w;
  w.put(kStop);
  comm.send(w.take(), 0, kTag);
}

DataSetPartition generate_partition(const Comm& comm) {
  DataSetPartition p;
  if (!comm.parallel()) return p;
  const int K = comm.size(), me = comm.rank();
  p.processes = K;
  p.simulates_here = [K, me](int i) { return i % K == me; };
  p.agree_first = [&comm](int committed) {
    ByteWriter w;
    w.put(static_cast<std::int64_t>(committed));
    Bytes b = w.take();
    comm.broadcast(b);
    ByteReader in(b);
    std::int64_t first = 0;
    in.get(first);
    return static_cast<int>(first);
  };
  if (comm.is_root()) {
    p.receive = [&comm, K](int i) -> std::optional<SimulationRecord> {
      // Stopped (SIGINT/SIGTERM) while waiting: commit nothing more, whatever the others do.
      while (!comm.has_message(i % K, kTag)) {
        if (interrupted()) return std::nullopt;
        std::this_thread::sleep_for(std::chrono::milliseconds(1));
      }
      std::optional<SimulationRecord> rec = unpack_simulation(comm.receive(i % K, kTag));
      if (rec && rec->index != i)
        throw IoError("generate: rank " + std::to_string(i % K) + " sent simulation " + std::to_string(rec->index) +
                      " where " + std::to_string(i) + " was due");
      return rec;
    };
  } else {
    p.ship = [&comm](const SimulationRecord& rec) { comm.send(pack_simulation(rec), 0, kTag); };
  }
  return p;
}

}  // namespace dc::cli
