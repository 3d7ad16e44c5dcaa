// Metrics: one number (or one state vector) measured from one run, for convergence
// studies and sweeps.
//
//   qpos[hinge]@2       the value of a path at t = 2 s
//   period(qpos[hinge]) the mean period of a path's oscillation, s
//   maxabs(qvel[hinge]) the largest |value| of a path over the run
//   energy_drift        (E(T) - E(0)) / max kinetic energy, total energy E = potential + kinetic
//   state@2             the whole state (qpos, qvel, act) at t = 2 s; errors are norms
//
// Example:
//   plumb::Metric q2 = plumb::ParseMetric(model, "qpos[hinge]@2");
//   plumb::Measurement v = plumb::Measure(model, sets, q2, 0.002, 2.0);
//
// Thread-safety: ParseMetric and Measure only read `model` (Measure runs on a copy of its own)
// and may be called from several threads at once, also on one Model. MeasureInPlace writes
// `work` and `data`: give each thread its own, as a sweep's workers have. Measure and
// MeasureInPlace take (and drop) the calling thread's pending MuJoCo warnings (TakeMujocoWarnings).

#ifndef PLUMB_INCLUDE_PLUMB_METRIC_H_
#define PLUMB_INCLUDE_PLUMB_METRIC_H_

#include <string>
#include <string_view>
#include <vector>

#include "plumb/model.h"
#include "plumb/path.h"
#include "plumb/stop.h"

namespace plumb {

enum class MetricKind { kValueAt, kPeriod, kMaxAbs, kEnergyDrift, kStateAt };

struct Metric {
  std::string text;  // as typed, e.g. "qpos[hinge]@2"
  MetricKind kind = MetricKind::kValueAt;
  Path path;        // for value@T, period and maxabs
  double time = 0;  // T for value@T and state@T, s
};

// Parses a metric. @throws PathError / ValueError naming the metric text.
Metric ParseMetric(const Model& model, std::string_view text);

// The run a metric needs when the user gives no --until: T for @T metrics, 20 s for
// period (several swings of a slow pendulum), 2 s otherwise (the chapter's run).
double DefaultDuration(const Metric& metric);

// One measured metric.
struct Measurement {
  double value = 0;           // the metric (for state@T: the state's Euclidean norm)
  std::vector<double> state;  // state@T only: qpos, qvel, act concatenated
  double scale = 1;           // what errors are compared with: half the range of PATH over the run
                              // (its swing, not its offset), the largest distance of the state from
                              // its start for state@T, the period itself, 1 for energy_drift
  bool ok = true;             // false when the metric could not be measured
  bool diverged = false;      // ... because the run diverged (else: the metric does not apply)
  std::string problem;        // why not (diverged at t = ..., fewer than two crossings, ...)
  long steps = 0;
};

// Runs `model` (copied: the argument is not changed) with `sets` applied, the timestep
// set to `timestep` (s), for `until` s, and measures `metric`. Divergence and
// unmeasurable metrics are reported through ok/problem, not thrown.
// @throws ValueError when `until` or the metric time is not a whole number of steps;
// ValueError / PathError when the model refuses `sets`; Interrupted when `stop` asks;
// MujocoError.
Measurement Measure(const Model& model, const std::vector<Assignment>& sets, const Metric& metric,
                    double timestep, double until, const StopToken& stop = {});

// Same, reusing `work` (a model of the same structure, e.g. a worker's copy made with
// Model::Clone) and `data` made from it, so sweeps allocate nothing per case.
// @throws as Measure does.
Measurement MeasureInPlace(const Model& nominal, Model& work, Data& data,
                           const std::vector<Assignment>& sets, const Metric& metric,
                           double timestep, double until, const StopToken& stop = {});

// Same for several metrics in one run `until` s long (each metric's own length: a value@T or
// state@T's T is `until`), one Measurement per metric, so a sweep measures a case's metrics
// of one length in one simulation; a divergence is every metric's. @throws as Measure does.
std::vector<Measurement> MeasureInPlace(const Model& nominal, Model& work, Data& data,
                                        const std::vector<Assignment>& sets,
                                        const std::vector<Metric>& metrics, double timestep,
                                        double until, const StopToken& stop = {});

}  // namespace plumb

#endif  // PLUMB_INCLUDE_PLUMB_METRIC_H_
