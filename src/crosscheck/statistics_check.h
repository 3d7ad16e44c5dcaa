// The statistics check: N randomized worlds (plumb rollout's --randomize, --ctrl-noise and
// --metric) run in CPU MuJoCo and in the engine with the same parameters, starts and controls;
// each metric's paired differences go through two one-sided tests against a stated margin.

#ifndef PLUMB_SRC_CROSSCHECK_STATISTICS_CHECK_H_
#define PLUMB_SRC_CROSSCHECK_STATISTICS_CHECK_H_

#include <vector>

#include "crosscheck/engine_session.h"
#include "plumb/crosscheck.h"

namespace plumb::internal {

// The metrics measured when none are given: the final position of the first free joint (x, y,
// z), else the final coordinate of up to four hinge or slide joints.
std::vector<Metric> DefaultCrosscheckMetrics(const Model& model, double until);

// Whether every world of the statistics check is the same world: nothing randomized and no
// control noise.
bool WorldsAreIdentical(const CrosscheckOptions& options);

// A metric's row when the worlds are identical: the engine met CPU MuJoCo N times on one
// world, which says nothing about the distribution, so a PASS (or an undecided WARN) becomes a
// SKIP that says so and how to vary the worlds; a FAIL stays a FAIL (one world's difference
// is a finding). Unchanged when the worlds differ.
void JudgeIdenticalWorlds(const CrosscheckOptions& options, CheckRow* row);

// `nominal` is the model as given (options.sets are applied per world, as plumb rollout does);
// `loaded` the one the engine holds (nominal with options.sets applied).
std::vector<CheckRow> StatisticsCheck(const Model& nominal, const Model& loaded,
                                      EngineSession& engine, const CrosscheckOptions& options);

}  // namespace plumb::internal

#endif  // PLUMB_SRC_CROSSCHECK_STATISTICS_CHECK_H_
