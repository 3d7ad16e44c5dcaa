// Timing rules every command shares: which timestep a run uses, and whether a time
// (a sampling interval, a metric time, a run length that is measured) falls on a whole
// number of steps. One function per rule, so run, verify, converge, sweep, rollout,
// audit and snapshot accept and refuse the same inputs with the same words.
//
// Example:
//   double dt = plumb::RunTimestep(model, sets);           // after --set opt.timestep=...
//   long stride = plumb::RequireWholeSteps(0.1, dt, "every", "0.1");
//   double every = plumb::DefaultEvery(dt);                // 0.1 s on whole steps
//
// Thread-safety: every function is pure (RunTimestep only reads the model): call them from any
// thread.

#ifndef PLUMB_INCLUDE_PLUMB_TIMING_H_
#define PLUMB_INCLUDE_PLUMB_TIMING_H_

#include <optional>
#include <string>
#include <vector>

#include "plumb/model.h"
#include "plumb/path.h"

namespace plumb {

// The timestep (s) a run of `model` uses once `sets` are applied: the value of the last
// assignment to opt.timestep in `sets`, else the model's own opt.timestep. A keyframe
// holds state only, so it never changes the timestep.
// @throws ValueError when that timestep is not a positive, finite number.
double RunTimestep(const Model& model, const std::vector<Assignment>& sets);

// The number of steps of `timestep` s that make up `time` s, when that is a whole number
// (relative tolerance 1e-9); std::nullopt otherwise, or when either is not finite or
// the timestep is not positive.
std::optional<long> WholeSteps(double time, double timestep);

// The checked form of WholeSteps, with the one error wording all commands use. `argument`
// and `value` name the time as the caller gave it ("every", "0.1"; "metric",
// "'qpos[hinge]@2'"), and `source` where the timestep comes from ("the model's timestep";
// empty for the timestep the run uses). Returns the number of steps.
// @throws ArgumentError when `time` is not a whole number of steps, or is fewer than
//         `min_steps` steps; the message names the two nearest times that are.
long RequireWholeSteps(double time, double timestep, const std::string& argument,
                       const std::string& value, const std::string& source = "",
                       long min_steps = 1);

// The number of steps a run to `until` s takes at `timestep`, as the chapter's loop
// `while (d->time < until) mj_step(m, d);` does: the whole number of steps when `until`
// is one (WholeSteps' tolerance), else rounded up. A run's end is the one time that may
// fall between steps. Expects until >= 0 and timestep > 0.
long StepsToReach(double until, double timestep);

// The default sampling interval for a model whose timestep is `timestep` s: the whole
// number of steps nearest to `wanted` s, at least one step (0.1 s at dt = 0.002; 0.09 s
// at dt = 0.03). Computed as steps * timestep.
double DefaultEvery(double timestep, double wanted = 0.1);

}  // namespace plumb

#endif  // PLUMB_INCLUDE_PLUMB_TIMING_H_
