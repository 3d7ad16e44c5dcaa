// Timestep convergence: run the same scenario at dt, dt/2, dt/4, ..., estimate the
// observed order of accuracy, extrapolate (Richardson) and recommend a timestep.
//
// Example:
//   plumb::ConvergenceResult r = plumb::Converge(model, sets, metric, 0.002, 4, 1e-3);
//   r.observed_order   // ~1 for Euler, ~4 for RK4 on the chapter's pendulum
//   r.recommended_dt   // the largest tested dt/2^k that, with every finer level, meets
//                      // tol * scale (RecommendedLevel)
//
// The levels run one model: MuJoCo raises every standard solref time constant to 2 * timestep
// (refsafe), so a ladder that only halved dt would clamp contacts, limits and equalities whose
// time constant is below 2 * dt0 less at each level, a model change it would read as error.
// Converge raises each such time constant to 2 * dt0 at every level, what the model runs with
// at dt0 (HoldSolref).
//
// Thread-safety: Converge only reads `model` (each level runs on a copy of its own) and starts no
// threads, so calls may run at once from several threads, also on one Model; it takes (and
// drops) the calling thread's pending MuJoCo warnings (TakeMujocoWarnings). The other functions
// are pure.

#ifndef PLUMB_INCLUDE_PLUMB_CONVERGE_H_
#define PLUMB_INCLUDE_PLUMB_CONVERGE_H_

#include <optional>
#include <string>
#include <vector>

#include "plumb/metric.h"
#include "plumb/path.h"
#include "plumb/stop.h"

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
  double dt = 0;     // s
  double value = 0;  // the metric at this dt
  double diff = 0;   // |value - value at dt/2| (a norm for state@T); NaN for the finest level
  double order = 0;  // log2(diff / next diff); NaN where undefined
  // Estimated error |value - extrapolated| (for state@T the geometric tail of the
  // differences); for the finest level the Richardson estimate |diff of the finest pair| /
  // (2^p - 1), flagged by `error_is_richardson`. NaN when not estimated: no order, or
  // the level's difference is round-off (never a fake zero).
  double error = 0;
  bool error_is_richardson = false;
  bool roundoff = false;  // diff is below the round-off level: it and the orders from it
                          // are noise (order is then NaN)
  // The largest difference between this level's value and a finer level's (norms for
  // state@T); for the finest level its difference to the next coarser one. NaN when a level
  // failed.
  double spread = 0;
};

// Whether `level` meets the tolerance `target` (tol * scale, the metric's units): its estimated
// error, where there is one, is within it, and its spread too (the finest level, which has
// nothing finer, is judged by its Richardson estimate alone when it has one; a level whose
// difference to the next is round-off meets any tolerance on that count).
bool LevelMeetsTolerance(const ConvergenceLevel& level, bool finest, double target);

// The recommendation rule that plumb converge and plumb verify share: the index of the
// coarsest level that, with every finer level, meets `target` (LevelMeetsTolerance), or -1.
// A level is never recommended above one that fails, however small its own estimate: the
// estimates of a rough sequence need not fall as dt shrinks. `levels` is coarsest first.
int RecommendedLevel(const std::vector<ConvergenceLevel>& levels, double target);

// The standard solref time constants (solref[0] > 0) of `model` below `floor` s, raised to it,
// as assignments to append to a run's own (their texts name the arrays): at every level of a
// ladder whose coarsest step is floor / 2 this holds the model MuJoCo runs at that step. A
// geom's is raised only when one of its contacts mixes (solmix, priority) below the floor; a
// contact between a raised geom and one above the floor then mixes a little softer than MuJoCo's
// clamp of the unraised mix would (the levels still run one model). Empty when none is below, or
// when refsafe is off (MuJoCo then clamps nothing). `held` (optional) gets how many rows each
// array had raised, e.g. "geom_solref (3), eq_solref (1)".
std::vector<Assignment> HoldSolref(const Model& model, double floor, std::string* held = nullptr);

struct ConvergenceResult {
  std::string model;  // the model's file
  std::string metric;
  double until = 0;                      // s, the run length of every level
  int integrator = 0;                    // mjtIntegrator of the runs, after `sets`
  double expected_order = 0;             // the integrator's order (ExpectedOrder), after `sets`
  std::vector<ConvergenceLevel> levels;  // coarsest first
  OrderEstimate estimate;
  double scale = 1;   // the metric's magnitude, errors are compared with tol * scale
  double tol = 1e-3;  // relative tolerance
  // The largest tested level (one of levels[].dt, never an extrapolated step) that, with
  // every finer level, meets tol * scale (RecommendedLevel); 0 if none.
  double recommended_dt = 0;
  // s: every standard solref time constant below it was raised to it at every level (MuJoCo's
  // 2 * dt floor at the coarsest level, HoldSolref); 0 when none was below, or refsafe is off.
  double solref_floor = 0;
  std::string solref_held;  // the arrays and rows raised, e.g. "geom_solref (3)"; or empty
  int max_contacts = 0;   // most contacts at once in the run at dt0
  std::string caveat;     // ContactCaveat(max_contacts): empty without contacts
  bool ok = true;         // false when a level diverged or could not be measured
  bool diverged = false;  // ... because a level diverged
  std::string problem;
};

// Measures `metric` at dt0 / 2^k for k = 0..halvings (with the model's integrator,
// or the one `sets` chooses) over `until` s, and analyses the sequence.
// @throws ValueError for halvings < 2 or a dt that does not divide the run; ValueError /
// PathError when the model refuses `sets`; Interrupted when `stop` asks; MujocoError.
ConvergenceResult Converge(const Model& model, const std::vector<Assignment>& sets,
                           const Metric& metric, double dt0, int halvings, double tol, double until,
                           const StopToken& stop = {});

// What plumb converge takes (the command's flags, the Python keywords): the start, the
// coarsest timestep and run length (unset: the model's timestep after `sets`, and the metric's
// DefaultDuration), the ladder and the tolerance.
struct ConvergeOptions {
  std::vector<Assignment> sets;
  std::optional<double> dt;
  int halvings = 4;
  double tol = 1e-3;
  std::optional<double> until;
  StopToken stop;  // when it asks, the ladder ends with Interrupted (default: never)
};

// Converge with the options resolved and checked. A metric that cannot be measured on this
// run (not a divergence: a period of a joint that never swings) is the caller's to change.
// @throws ArgumentError ("dt", "until", "tol", "halvings": not positive and finite; "metric":
// it cannot be measured, saying why); as Converge otherwise. A diverged level is a result
// (ok false, diverged true).
ConvergenceResult Converge(const Model& model, const Metric& metric,
                           const ConvergeOptions& options);

// What every convergence report says about the solref time constants: "solref time constants
// below 0.004 s held at 0.004 s across levels (MuJoCo's 2*dt floor at the coarsest level):
// geom_solref (3)"; empty when none was held.
std::string SolrefNote(const ConvergenceResult& result);

// The caveat every convergence report (converge's table and JSON, verify's convergence
// check) gives when contacts occur: contacts make trajectories non-smooth in time, so
// orders (even negative ones) and extrapolations are rough. Empty when max_contacts is 0.
std::string ContactCaveat(int max_contacts);

// The order the integrator is expected to show: Euler 1, RK4 4, implicit 1 (and
// implicitfast 1 on MuJoCo 3).
double ExpectedOrder(int integrator);

}  // namespace plumb

#endif  // PLUMB_INCLUDE_PLUMB_CONVERGE_H_
