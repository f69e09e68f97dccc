#pragma once
// `deepcontact generate` across MPI ranks (docs/cluster.md).
//
// Scheme: rank 0 is the writer, exactly as in a one-process run (DataSetWriter, OUT.partial,
// one flush per committed simulation); simulation i is simulated by rank i mod K with that
// rank's OpenMP workers; the other ranks send each finished simulation to rank 0 as one
// message, in index order, and rank 0 appends every simulation in index order. The file is
// therefore the one-process file, dataset for dataset, whatever K. Memory stays bounded: a
// large message is delivered only when rank 0 asks for it (MPI's rendezvous protocol), so a
// rank can be at most its look-ahead window ahead of the writer.
//
// Interruption: rank 0's file is committed simulation by simulation, so killing any rank (or
// the job) loses only simulations in flight, and `--resume` under any K continues from the
// committed ones. A rank that stops (SIGINT under srun) sends a stop message; rank 0 then
// commits what it has and ends the job (MPI_Abort, exit status 130).
#include <optional>

#include "cluster/comm.hpp"
#include "dc/cnn/data_set_generation.hpp"

namespace dc::cli {

/// The partition of generate_data_set over `comm` (serial: the default, no callbacks).
DataSetPartition generate_partition(const Comm& comm);

/// A non-writer rank's last word when it stops early (see above).
void send_generate_stop(const Comm& comm);

/// One simulation as a message and back (all fields; exposed for the tests).
Bytes pack_simulation(const SimulationRecord& rec);
/// nullopt for a stop message.
std::optional<SimulationRecord> unpack_simulation(const Bytes& message);

}  // namespace dc::cli
