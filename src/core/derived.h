// The derived quantities mj_forward leaves out unless a model flag or a sensor asks for
// them, computed on demand so that no path reads a value MuJoCo never wrote.

#ifndef PLUMB_SRC_CORE_DERIVED_H_
#define PLUMB_SRC_CORE_DERIVED_H_

#include <mujoco/mujoco.h>

namespace plumb::internal {

// Completes what mj_forward computed for the state in `d`: energy (mj_energyPos and
// mj_energyVel, which mj_forward runs only with <flag energy="enable"/>),
// subtree_linvel and subtree_angmom (mj_subtreeVel, only for subtree sensors), and
// cacc, cfrc_int and cfrc_ext (mj_rnePostConstraint, only for acceleration and force
// sensors). Call right after mj_forward. Writes only those outputs: the state, the
// warm start and everything mj_step uses are untouched, so the trajectory that
// follows is bit-identical.
void CompleteDerived(const mjModel* m, mjData* d);

}  // namespace plumb::internal

#endif  // PLUMB_SRC_CORE_DERIVED_H_
