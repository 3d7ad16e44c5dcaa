// The stage check's comparison: CPU MuJoCo's and the engine's values of one step from the same
// states, stage by stage in the order a step computes them. Contacts are matched by geom pair,
// constraint rows by type and element, never by position in a list. Tolerances are float32-aware:
// a stage's tolerance is its factor times float32's epsilon times the stage's scale
// (docs/crosscheck.md derives the factors).

#ifndef PLUMB_SRC_CROSSCHECK_STAGE_COMPARE_H_
#define PLUMB_SRC_CROSSCHECK_STAGE_COMPARE_H_

#include <vector>

#include "crosscheck/engine_session.h"
#include "plumb/check.h"
#include "plumb/model.h"

namespace plumb::internal {

// The stages in order: "kinematics", "mass_matrix", "contacts", "constraint_rows",
// "constraint_forces", "accelerations", "sensors", "next_state".
const std::vector<const char*>& StageNames();

// Factor of float32's epsilon each stage's tolerance takes (the stage's scale times this).
double StageFactor(const char* stage);

// One row per stage: PASS where the engine agrees within tolerance; FAIL for the first stage
// that disagrees (named down to the body, dof, geom pair, constraint or sensor), WARN for
// later stages that disagree too (they follow from it). `times` are the states' times.
std::vector<CheckRow> CompareStages(const Model& model, const StageValues& cpu,
                                    const StageValues& engine, const std::vector<double>& times);

}  // namespace plumb::internal

#endif  // PLUMB_SRC_CROSSCHECK_STAGE_COMPARE_H_
