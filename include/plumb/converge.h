// Timestep convergence: run the same scenario at dt, dt/2, dt/4, ..., estimate the
// observed order of accuracy, extrapolate (Richardson) and recommend a timestep.
//
// Example:
//   plumb::ConvergenceResult r = plumb::Converge(model, sets, metric, 0.002, 4, 1e-3);
//   r.observed_order   // ~1 for Euler, ~4 for RK4 on the chapter's pendulum
//   r.recommended_dt   // the largest dt/2^k whose estimated error is below tol * scale

#ifndef PLUMB_INCLUDE_PLUMB_CONVERGE_H_
#define PLUMB_INCLUDE_PLUMB_CONVERGE_H_

#include <string>
#include <vector>

#include "plumb/metric.h"

namespace plumb {

// The order of accuracy p seen in values v_i computed with timesteps dt_i = dt_0 / 2^i.
struct OrderEstimate {
  bool resolved = false;    // false when no two successive differences stand above noise
  double order = 0;         // p from the finest pair of differences above noise
  double extrapolated = 0;  // Richardson: v_j + (v_j - v_{j-1}) / (2^p - 1), or the finest value
  int noise_from = -1;      // first difference index that is round-off, or -1
  std::string note;         // what was (not) done and why
};

// Estimates the order from the successive differences `diffs[i]` = |v_i - v_{i+1}|
// (norms for vectors) of values `values` (finest last). Differences below `noise` are
// round-off and are not used. Halving must be by exactly 2.
OrderEstimate EstimateOrder(const std::vector<double>& values, const std::vector<double>& diffs,
                            double noise);

struct ConvergenceLevel {
  double dt = 0;          // s
  double value = 0;       // the metric at this dt
  double diff = 0;        // |value - value at dt/2| (a norm for state@T); NaN for the finest level
  double order = 0;       // log2(diff / next diff); NaN where undefined
  double error = 0;       // estimated error |value - extrapolated|; NaN when unresolved
  bool roundoff = false;  // diff is below the round-off level: it and the orders from it
                          // are noise (order is then NaN)
};

struct ConvergenceResult {
  std::string metric;
  std::vector<ConvergenceLevel> levels;  // coarsest first
  OrderEstimate estimate;
  double scale = 1;           // the metric's magnitude, errors are compared with tol * scale
  double tol = 1e-3;          // relative tolerance
  double recommended_dt = 0;  // largest dt0 * 2^-k (k >= -1) predicted to meet tol; 0 if none;
                              // dt0 when every level agrees to round-off
  bool ok = true;             // false when a level diverged or could not be measured
  bool diverged = false;      // ... because a level diverged
  std::string problem;
};

// Measures `metric` at dt0 / 2^k for k = 0..halvings (with the model's integrator,
// or the one `sets` chooses) over `until` s, and analyses the sequence.
// @throws ValueError for halvings < 2 or a dt that does not divide the run.
ConvergenceResult Converge(const Model& model, const std::vector<Assignment>& sets,
                           const Metric& metric, double dt0, int halvings, double tol,
                           double until);

// The order the integrator is expected to show: Euler 1, RK4 4, implicit 1 (and
// implicitfast 1 on MuJoCo 3).
double ExpectedOrder(int integrator);

}  // namespace plumb

#endif  // PLUMB_INCLUDE_PLUMB_CONVERGE_H_
