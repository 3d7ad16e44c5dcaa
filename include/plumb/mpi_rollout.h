// Multi-node rollouts over MPI: an optional part, its own library (plumb::mpi, link it beside
// plumb::plumb). Built with OpenMPI when PLUMB_WITH_MPI is on and MPI is found; otherwise these
// say "not active" and a program runs in one process.
//
// Under `mpirun -np K plumb rollout ...`, rank 0 hands out chunks of rollout indices to
// ranks 1..K-1 as they ask for work (so slow nodes never hold the batch back), gathers
// their results, and emits them in index order: output and results store are the same as
// a single-process run's.
//
// Thread-safety: MPI's world is one per process: call these from the thread that called
// MpiInit (MpiRollout runs its rollouts on the rollout pool's threads itself). They throw
// plumb::Error for a damaged message between ranks, and MpiRollout what RolloutPool::Run
// throws (Interrupted when `stop` asks).

#ifndef PLUMB_INCLUDE_PLUMB_MPI_ROLLOUT_H_
#define PLUMB_INCLUDE_PLUMB_MPI_ROLLOUT_H_

#include <functional>
#include <vector>

#include "plumb/rollout.h"
#include "plumb/stop.h"

namespace plumb {

// Initialises MPI when the process was started by an MPI launcher; a no-op otherwise.
void MpiInit(int* argc, char*** argv);
void MpiFinalize();

// True when MPI is initialised with more than one rank.
bool MpiActive();
int MpiRank();

// Runs the rollouts of `indices` across the ranks. On rank 0 `emit` receives every result
// in the order of `indices`; other ranks only compute and return when the work is done.
// Collective: rank 0 says whether the batch goes ahead (its set-up, such as opening the
// results store, succeeded); every rank returns rank 0's answer. Without MPI, `ok`.
bool MpiGo(bool ok);

// Stops every rank with `code` after an error on one rank that the others cannot see
// (they would otherwise wait for it forever). Does nothing without an active MPI world
// or before MpiGo(true): until then every rank meets the same errors.
void MpiAbortOnError(int code);

// A worker rank stops its current chunk when `stop` asks (Interrupted), as RolloutPool::Run
// does. @throws Error without MPI, or when a message between ranks is damaged.
void MpiRollout(const Model& model, const RolloutSpec& spec, const std::vector<long>& indices,
                const std::function<void(const RolloutResult&)>& emit, const StopToken& stop = {});

}  // namespace plumb

#endif  // PLUMB_INCLUDE_PLUMB_MPI_ROLLOUT_H_
