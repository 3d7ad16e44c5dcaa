// Multi-node rollouts over MPI (built with PLUMB_WITH_MPI; without it these say "not
// active" and plumb runs in one process).
//
// Under `mpirun -np K plumb rollout ...`, rank 0 hands out chunks of rollout indices to
// ranks 1..K-1 as they ask for work (so slow nodes never hold the batch back), gathers
// their results, and emits them in index order: output and results store are the same as
// a single-process run's.

#ifndef PLUMB_APPS_PLUMB_MPI_H_
#define PLUMB_APPS_PLUMB_MPI_H_

#include <functional>

#include "plumb/rollout.h"

namespace plumb::cli {

// Initialises MPI when the process was started by an MPI launcher; a no-op otherwise.
void MpiInit(int* argc, char*** argv);
void MpiFinalize();

// True when MPI is initialised with more than one rank.
bool MpiActive();
int MpiRank();

// Runs the rollouts of `indices` across the ranks. On rank 0 `emit` receives every result
// in the order of `indices`; other ranks only compute and return when the work is done.
void MpiRollout(const Model& model, const RolloutSpec& spec, const std::vector<long>& indices,
                const std::function<void(const RolloutResult&)>& emit);

}  // namespace plumb::cli

#endif  // PLUMB_APPS_PLUMB_MPI_H_
