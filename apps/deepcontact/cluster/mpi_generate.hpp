#pragma once
// `deepcontact generate` across MPI ranks (docs/cluster.md).
//
// Scheme: every rank writes its own shards — simulation i is simulated by rank i mod K with
// that rank's OpenMP workers and committed by that rank as OUT.shards/RUN/sim-i.h5 (tmp,
// fsync, rename; data_set_generation.hpp). Rank 0 checks the request, holds OUT.lock, names
// the run (broadcast to the others) and, once every rank has stopped (a sum over the ranks),
// writes the manifest OUT when all M shards are in. No simulation travels between ranks, so
// rank 0 is no bottleneck; the shards, and so the data set, are the one-process ones
// whatever K.
//
// Interruption: a shard is complete or absent, so killing any rank (or the job) loses only
// the simulations in flight, and `--resume` under any K continues from the committed ones.
// SIGINT/SIGTERM/SIGUSR1 stop a rank's workers at the next step; the rank then joins the
// final sum, and the job ends with "interrupted" when shards are missing.
#include "cluster/comm.hpp"
#include "dc/cnn/data_set_generation.hpp"

namespace dc::cli {

/// The partition of generate_data_set over `comm` (serial: the default, one process).
DataSetPartition generate_partition(const Comm& comm);

}  // namespace dc::cli
