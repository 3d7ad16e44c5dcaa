// Which constraints MuJoCo softens with its solref safety limit: a standard solref (timeconst,
// dampratio both > 0) has its time constant raised to two timesteps unless the refsafe flag is
// disabled (compat::ReferenceTimeconstClamped). The rule "which rows of which solref arrays are
// below a floor and make a constraint" lives here once, for verify's convergence ladder
// (HoldSolref) and the audit's structure.solref_clamp.

#ifndef PLUMB_SRC_CORE_SOLREF_H_
#define PLUMB_SRC_CORE_SOLREF_H_

#include <mujoco/mujoco.h>

#include <cmath>
#include <string>
#include <vector>

namespace plumb::internal {

// One solref row whose standard time constant is below a floor and makes a constraint.
struct SolrefBelow {
  std::string array;  // "geom_solref", "jnt_solref", ... (compat::ClampedSolrefArrays)
  long row = 0;
  double timeconst = 0;  // solref[0] as the model holds it
  double dampratio = 0;  // solref[1]
  // a geom's row: the lowest time constant its dynamic contacts start from, as mj_contactParam
  // chooses it (the higher priority geom's own, else the two mixed by their solmix weights)
  // over the geoms it may touch (contype/conaffinity, less the same weld group, the
  // parent-child filter, <exclude>d body pairs and geom pairs an explicit <pair> sets); NaN
  // for other rows
  double contact = NAN;
};

// Every row whose standard time constant is below `floor` and makes a constraint, array by
// array in ClampedSolrefArrays' order, whether or not refsafe is on: a limited joint or
// tendon, a dof or tendon with friction loss, a geom with a dynamic contact below the floor, an
// explicit pair, every equality and flex with contacts; pair_solreffriction only under the
// elliptic cone (the pyramidal one ignores it). Under <flag override="enable"/> opt.o_solref
// replaces every contact's solref and solreffriction, and acts when some contact can happen.
// Constraint kinds the model's disable flags switch off make none.
std::vector<SolrefBelow> ActingSolrefsBelow(const mjModel* m, double floor);

// The rows MuJoCo raises to `floor` = 2 x timestep: ActingSolrefsBelow, none when refsafe is
// disabled (MuJoCo then clamps nothing).
std::vector<SolrefBelow> SolrefsBelow(const mjModel* m, double floor);

}  // namespace plumb::internal

#endif  // PLUMB_SRC_CORE_SOLREF_H_
