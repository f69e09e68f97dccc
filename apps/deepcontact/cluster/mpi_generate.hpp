#pragma once
// `deepcontact generate` across MPI ranks (docs/cluster.md). Simulation i is run by rank
// i mod K with its OpenMP workers and committed by that rank as OUT.shards/RUN/sim-i.h5
// (data_set_generation.hpp). Rank 0 checks the request, holds OUT.lock, names the run
// (broadcast) and, when every rank has stopped (a sum over the ranks), writes the manifest if
// all M shards are in. No simulation travels between ranks; the data set is the one-process
// one whatever K. A shard is complete or absent, so killing any rank loses only simulations in
// flight and `--resume` under any K continues. SIGINT/SIGTERM/SIGUSR1 stop a rank's workers at
// the next step; the job ends "interrupted" when shards are missing.
#include "cluster/comm.hpp"
#include "dc/cnn/data_set_generation.hpp"

namespace dc::cli {

/// The partition of generate_data_set over `comm` (serial: the default, one process).
DataSetPartition generate_partition(const Comm& comm);

}  // namespace dc::cli
