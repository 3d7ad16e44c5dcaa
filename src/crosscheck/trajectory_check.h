// The trajectory check: open-loop runs from K starts in CPU MuJoCo, in CPU MuJoCo rounding its
// state to float32 after every step (the chaos baseline), and in the engine; when each joint's
// signal parts from CPU MuJoCo's, and whether the engine parts much sooner than rounding alone
// explains.

#ifndef PLUMB_SRC_CROSSCHECK_TRAJECTORY_CHECK_H_
#define PLUMB_SRC_CROSSCHECK_TRAJECTORY_CHECK_H_

#include <vector>

#include "crosscheck/engine_session.h"
#include "plumb/crosscheck.h"

namespace plumb::internal {

// One row (FAIL names the signal that parts first), and the per-signal times in `tracks`.
std::vector<CheckRow> TrajectoryCheck(const Model& model, const std::vector<const mjData*>& starts,
                                      EngineSession& engine, const CrosscheckOptions& options,
                                      std::vector<DivergenceTrack>* tracks);

}  // namespace plumb::internal

#endif  // PLUMB_SRC_CROSSCHECK_TRAJECTORY_CHECK_H_
