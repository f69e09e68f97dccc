// generate_partition (mpi_generate.hpp).
#include "cluster/mpi_generate.hpp"

#include <string>

namespace dc::cli {

DataSetPartition generate_partition(const Comm& comm) {
  DataSetPartition p;
  if (!comm.parallel()) return p;
  p.processes = comm.size();
  p.rank = comm.rank();
  p.broadcast = [&comm](const std::string& text) {
    Bytes b(text.begin(), text.end());
    comm.broadcast(b);
    return std::string(b.begin(), b.end());
  };
  p.sum = [&comm](long value) {
    double v[] = {static_cast<double>(value)};
    comm.sum(v);
    return static_cast<long>(v[0]);
  };
  return p;
}

}  // namespace dc::cli
