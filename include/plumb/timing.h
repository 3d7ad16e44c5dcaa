// Timing rules every command shares: which timestep a run uses, whether a time (a
// sampling interval, a metric time, a run length that is measured) falls on a whole number
// of steps, how many steps a time takes (at most 2^53), and whether what that many steps
// hold fits in memory. One function per rule, so run, verify, converge, sweep, rollout,
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

// The most steps a run may take: a run counts its steps in a long and times them as
// step * timestep, both exact up to 2^53 (9.0e15).
inline constexpr double kMostSteps = 9007199254740992.0;  // 2^53

// StepsToReach, checked: the one rule by which every command and Python function turns a
// time it was given (a run's end, a picture's time, a bridge's stop) into steps. `argument`
// and `value` name the time as the caller gave it ("until", "1e+17"; "at", "0.5"); an empty
// `value` shows `until` as a number; `source` says where the timestep comes from, as
// RequireWholeSteps takes it ("the convergence ladder's finest level").
// @throws ArgumentError when `until` is NaN, negative or infinite, or takes more than
//         kMostSteps steps of `timestep`; ValueError for a timestep that is not positive.
long RequireStepsToReach(double until, double timestep, const std::string& argument,
                         const std::string& value = "", const std::string& source = "");

// The check before a buffer of `bytes` is allocated for what a caller asked (every row of
// `count` rollouts, every frame of a film): refuses what this machine's memory cannot hold,
// instead of failing with std::bad_alloc after work was done. `what` says what the bytes hold
// ("the rows of 1e+12 rollouts"); `argument` and `value` name the argument that asked.
// @throws ArgumentError when `bytes` is not finite or passes the physical memory.
void RequireMemoryFor(double bytes, const std::string& what, const std::string& argument,
                      const std::string& value);

// The default sampling interval for a model whose timestep is `timestep` s: the whole
// number of steps nearest to `wanted` s, at least one step (0.1 s at dt = 0.002; 0.09 s
// at dt = 0.03). Computed as steps * timestep.
double DefaultEvery(double timestep, double wanted = 0.1);

}  // namespace plumb

#endif  // PLUMB_INCLUDE_PLUMB_TIMING_H_
