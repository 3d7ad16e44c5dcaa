// Parameter identification: fit model parameters so that replaying logs (plumb/replay.h)
// matches what was measured, and say how well each parameter is known.
//
// - Nonlinear least squares (Ceres Solver, Levenberg-Marquardt) over the replay error of
//   every measured sample of every log, each signal weighted by its noise: a first solve
//   weights by the signals' spread, then each signal's noise is estimated from its residuals
//   and the problem is solved again with those weights, so the residuals are in units of
//   their own noise.
// - Parameters are plumb paths of model arrays (dof_damping[hinge], body_mass[payload],
//   geom_friction[foot][0], `*` for every row). Each is solved in units of its nominal value
//   (or of its bounds' width when the nominal is 0), so a mass and a friction coefficient are
//   solved together well. Bounds: given PATH=LO:HI, else [0, inf) for quantities MuJoCo does
//   not take negative.
// - The Jacobian is by central differences, its columns run in parallel on the worker pool;
//   each run starts from the nominal model, so the result is the same for any thread count.
// - Standard errors from the Jacobian at the optimum, scaled by the residual variance;
//   correlations; identifiability warnings (a parameter the logs barely see, or two that
//   move together above 0.95), each naming what log would settle it.
// - Misspecification: each signal's residuals at the optimum are tested for structure over time
//   that noise lacks (lag-1 autocorrelation, a runs test of the signs), and the fitted model's
//   replay against the nominal one's. When the model cannot explain the logs, the standard
//   errors are Newey–West's (robust to the residuals' correlation over time), or withheld
//   when those cannot be had; IdentifyResult says which and why.
// - A pure delay on the inputs or on the measurements: scanned in whole timesteps, with the
//   parameters refitted at the best delay.
//
// Example:
//   plumb::IdentifyOptions o;
//   o.fit = {"dof_damping[hinge]"};
//   plumb::IdentifyResult r = plumb::Identify(model, {log}, o);
//   r.estimates[0].value, r.estimates[0].std_error
//
// Thread-safety: Identify runs its simulations on options.threads threads (0: one per core) of a
// TBB arena, each on its own copy of `model`; `model` and `logs` are only read, so calls may run
// at once, also on one Model. ApplyEstimates writes `model`: no other thread may use it
// meanwhile. MuJoCo warnings of the runs stay with the threads that ran them (TakeMujocoWarnings),
// which may include the calling thread.

#ifndef PLUMB_INCLUDE_PLUMB_IDENTIFY_H_
#define PLUMB_INCLUDE_PLUMB_IDENTIFY_H_

#include <cmath>
#include <string>
#include <vector>

#include "plumb/model.h"
#include "plumb/path.h"
#include "plumb/replay.h"
#include "plumb/robot_log.h"
#include "plumb/stop.h"

namespace plumb {

// One free parameter.
struct FitParameter {
  Path path;  // one element of a model array
  double nominal = 0;
  double lo = -INFINITY, hi = INFINITY;
  double scale = 1;  // the unit it is solved in
};

enum class DelayKind { kNone, kInput, kSensor };

struct IdentifyOptions {
  std::vector<std::string> fit;     // paths; `*` rows expand
  std::vector<std::string> bounds;  // PATH=LO:HI
  ReplayOptions replay;             // window; the delays, when not estimated
  DelayKind delay = DelayKind::kNone;
  double max_delay = 0.1;    // s: the delay scan's range
  int threads = 0;           // 0: every core
  int max_iterations = 100;  // per solve (the first, each delay's, the noise-weighted one)
  StopToken stop;            // when it asks, Identify ends with Interrupted (default: never)
};

struct Estimate {
  std::string path;
  double nominal = 0;
  double value = 0;
  // The standard error given (IdentifyResult::std_errors says which kind): classical, or
  // Newey–West's when the model is misspecified; NaN when withheld.
  double std_error = NAN;
  double lo = -INFINITY, hi = INFINITY;
  bool at_bound = false;   // the optimum sits on a bound (its standard error then means little)
  double sensitivity = 0;  // how much a 100 % change moves the fit, in units of the noise
  double classical_std_error = NAN;  // from the Jacobian at the optimum and the residual variance
};

// One signal's residuals at the optimum (in units of its noise), tested for what white noise
// does not have.
struct ResidualStructure {
  std::string log;     // the log's source
  std::string column;  // as the log names it
  long samples = 0;
  double autocorrelation = NAN;    // lag-1, about the residuals' mean
  double autocorrelation_z = NAN;  // autocorrelation * sqrt(samples): about N(0, 1) for noise
  double runs_z = NAN;      // Wald–Wolfowitz runs test of the signs: about N(0, 1) for noise;
                            // negative: long runs of one sign (slow structure)
  double rms = 0;           // of the residuals, in the signal's units
  bool exact = false;       // matched to rounding (rms below 1e-9 of the signal's largest value):
                            // its residuals are not noise, and are not judged
  bool structured = false;  // either |z| above Misspecification::threshold
};

// Whether the model (with the fitted values) cannot explain the logs up to their noise.
struct Misspecification {
  bool detected = false;
  std::string reason;  // one line: the evidence (signal, autocorrelation, runs z, fit against
                       // nominal), or that none was found
  // |z| above which a signal counts as structured: the false-alarm rate over all signals on
  // white noise (two two-sided tests each, Bonferroni) is `false_alarm`; never below 4
  double threshold = 4;
  double false_alarm = 0;
  std::vector<ResidualStructure> signals;  // each log's signals in turn
  long structured = 0;                     // how many signals are
  // Half the sum of squared residuals of the nominal and the fitted model replayed from the
  // logged start (ReplayResult before/after), both on the final weights.
  double before_cost = NAN, after_cost = NAN;
  // after_cost exceeds before_cost by more than the logged start's noise and chance allow:
  // by 10 %, and 2 x the excess above k + 4 sqrt(2k) for k unknowns fitted
  bool worse_than_nominal = false;
};

// Which standard errors an IdentifyResult gives.
enum class StdErrorKind {
  kClassical,  // the Jacobian and the residual variance: the model explains all but the noise
  kNeweyWest,  // the Newey–West sandwich: the model is misspecified and the residuals correlate
  kWithheld,   // misspecified, and no robust standard error could be had
};

// "classical", "newey-west", "withheld".
const char* StdErrorKindName(StdErrorKind kind);

struct StdErrors {
  StdErrorKind kind = StdErrorKind::kClassical;
  int bandwidth = 0;  // Newey–West's lags (Bartlett kernel), for the longest series
  std::string why;    // a sentence: why these, or why none
};

struct IdentifyResult {
  std::vector<Estimate> estimates;
  std::vector<std::vector<double>> correlation;  // [i][j], of the classical covariance
  std::vector<double> singular_values;           // of the column-normalised Jacobian, largest = 1
  std::vector<std::string> warnings;             // identifiability, bounds
  std::vector<double> first_pass_cost;  // per iteration, weighted by the log's noise (differences)
  std::vector<double> cost;             // per iteration of the noise-weighted solve
  int first_pass_iterations = 0;        // of the first solve
  int iterations = 0;                   // of the noise-weighted solve (0 when not solved again)
  // The largest relative change from a signal's first weight to the noise its residuals show;
  // within 15 % the first solve's estimates stand, else the problem is solved again.
  double weight_change = 0;
  bool solved_again = true;
  long runs = 0;  // simulations of the logs (each of every log) for the solves and the errors
  // What the runs were: Jacobians taken, each one run per model parameter, one per group of
  // start-state offsets (the k-th offset of every window is one group, since an offset moves
  // only its own window) and one at the point; the rest are the solver's trial points. A run
  // already made at the same point is not made again.
  long jacobians = 0;
  long jacobian_runs = 0;      // of `runs`, made for the Jacobians
  long runs_per_jacobian = 0;  // parameters + start_groups + 1
  long start_unknowns = 0;     // start-state offsets fitted (0: the logged starts are used)
  long start_groups = 0;
  // Bates and Watts's relative offset where the fit ended: the Gauss–Newton step still left,
  // over sqrt(unknowns) standard errors. About 0 at a best fit; the solve stops below 0.01, and
  // above 1 the fit warns that it stopped short (a problem far from linear).
  double relative_offset = NAN;
  bool converged = false;
  std::string termination;  // Ceres's words
  long residuals = 0;
  // 2 cost / (residuals - unknowns): about 1 when the model explains all but the noise, and
  // about 1 too whenever the problem was solved again with the residuals' rms as the noise;
  // misspecification says whether the model does
  double residual_variance = NAN;
  Misspecification misspecification;
  StdErrors std_errors;
  double delay = 0;                                   // s, estimated (DelayKind) or as given
  std::vector<std::pair<double, double>> delay_scan;  // (delay, cost) of the last scan
  std::vector<std::vector<double>> noise;             // [log][signal]: estimated sigma
  std::vector<ReplayResult> before, after;            // per log: nominal and fitted model
};

// The delay to estimate, as `plumb identify --delay` names it: "" none, "ctrl" the inputs',
// "sensor" the measurements'. @throws ArgumentError (argument "delay") otherwise.
DelayKind ParseDelayKind(const std::string& text);

// Checks options a caller passes (not the paths: ResolveFitParameters does): @throws
// ArgumentError (argument "window", "max_delay", "threads" or "max_iterations") for a window that
// is negative or not finite, a longest delay not above 0, a negative thread count or fewer than
// one iteration.
void CheckIdentifyOptions(const IdentifyOptions& options);

// Resolves and checks the parameters to fit. @throws PathError for an unknown path;
// ValueError for a path that is not a model parameter, an integer field, bounds that are not
// LO:HI with LO < HI around the nominal, or a parameter named twice.
std::vector<FitParameter> ResolveFitParameters(const Model& model,
                                               const std::vector<std::string>& fit,
                                               const std::vector<std::string>& bounds);

// Fits. @throws PathError / ValueError as ResolveFitParameters does; ValueError for fewer
// residuals than parameters, an input delay without input columns, or windows the logs lack the
// state for (see WindowStarts); MujocoError; Interrupted when options.stop asks.
IdentifyResult Identify(const Model& model, const std::vector<RobotLog>& logs,
                        const IdentifyOptions& options);

// Writes the estimates into `model` (mj_setConst when an array changed).
// @throws PathError / ValueError as WriteValues does (a result of another model); MujocoError.
void ApplyEstimates(Model& model, const IdentifyResult& result);

// The classical covariance of the estimates, [i][j] = correlation[i][j] x the classical standard
// errors of i and j (Estimate::classical_std_error); NaN where those are.
std::vector<std::vector<double>> ClassicalCovariance(const IdentifyResult& result);

// A copy of `model` with the estimates written in (ApplyEstimates). @throws as it does.
Model FittedModel(const Model& model, const IdentifyResult& result);

// A log held out of the fit, replayed on the nominal and the fitted model.
struct HeldOutLog {
  const RobotLog* log = nullptr;
  ReplayResult nominal, fitted;
};

// Replays `log` (not fitted) on `model` and on `fitted` (FittedModel), the fitted one with the
// estimated delay when one was estimated. @throws as Replay does.
HeldOutLog ReplayHeldOut(const Model& model, const Model& fitted, const RobotLog& log,
                         const IdentifyOptions& options, const IdentifyResult& result);

// Writes the MJCF `source_xml` with the fitted values of `fitted` (FittedModel) to `out`
// (SaveXmlWithParameters: whole or not at all). @throws as SaveXmlWithParameters does.
void SaveFittedXml(const std::string& source_xml, const Model& fitted, const IdentifyResult& result,
                   const std::string& out);

// Writes the MJCF of `nominal` with the fitted values of `fitted` to `out` (SaveFittedXml): the
// MJCF is `source` when given, else the file `nominal` was loaded from, else (a model without
// one: a mujoco.MjModel, Model::Borrow) the XML MuJoCo parsed last when that is `nominal`'s
// (SourceMismatch: it compiles on its own to the same elements).
// @throws ValueError when there is no such MJCF, saying what to give; as SaveFittedXml does.
void SaveFittedModel(const Model& nominal, const Model& fitted, const IdentifyResult& result,
                     const std::string& out, const std::string& source = "");

// What the solves did, in a sentence: iterations and cost of each, whether the problem was
// solved again with the residuals' noise, how it ended and how many runs of the logs it took.
std::string DescribeSolves(const IdentifyResult& result);

// What the simulations of the logs went to (IdentifyResult::jacobians and the counts beside it),
// one clause: the end of DescribeSolves.
std::string DescribeRuns(const IdentifyResult& result);

// The residual variance in a line. With no misspecification found, with what it means (about 1
// when the model explains all but the noise); else that it says nothing of the model here,
// where the warning (misspecification.reason) says what does.
std::string DescribeResidualVariance(const IdentifyResult& result);

}  // namespace plumb

#endif  // PLUMB_INCLUDE_PLUMB_IDENTIFY_H_
