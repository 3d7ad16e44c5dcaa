// plumb verify: the chapter's credibility protocol as a battery of checks on any model.
//
// Every check yields one row: PASS, WARN, FAIL or SKIP (with the reason), the measured
// value, the reference it is held against, their relative error, and a one-line
// explanation a student understands. Generic models get every check that applies;
// a single hinge under gravity (recognised from the compiled model) also gets the
// analytic references, the chapter's three experiments and its exercises.
//
// Every run starts from the model's reference pose (plumb/keyframe.h FindReferencePose: the
// keyframe options.keyframe names, else keyframe "home", else "test", else qpos0) with
// options.sets on top, as audit's runs do; the report says which (VerifyReport::start).
//
// Example:
//   plumb::VerifyOptions options;
//   options.sets = {plumb::ParseAssignment(model, "qpos[hinge]=0.7")};
//   plumb::VerifyReport report = plumb::Verify(model, options);
//   report.failed()  // true when any check FAILed
//
// Thread-safety: Verify only reads `model` (each run uses a copy of its own) and starts no
// threads, so calls may run at once from several threads, also on one Model. Its density
// exercise compiles MJCF with Model::FromXmlString, serialised with Model::Load. It takes (and
// drops) the calling thread's pending MuJoCo warnings (TakeMujocoWarnings).

#ifndef PLUMB_INCLUDE_PLUMB_VERIFY_H_
#define PLUMB_INCLUDE_PLUMB_VERIFY_H_

#include <optional>
#include <string>
#include <vector>

#include "plumb/check.h"
#include "plumb/converge.h"
#include "plumb/model.h"
#include "plumb/path.h"
#include "plumb/stop.h"

namespace plumb {

struct VerifyOptions {
  // The keyframe every run starts from, by name ("#0" by id); empty: the reference pose
  // (keyframe "home", else "test", else qpos0).
  std::string keyframe;
  std::vector<Assignment> sets;  // applied on top of the keyframe, in order
  double tol = 1e-2;  // relative tolerance for convergence and energy, of the metric's scale
  // Nominal run length, s: a positive whole number of timesteps (the convergence ladder's
  // coarsest level is the model's own timestep). Unset picks 2 s (the chapter's), and for models
  // that are not a single pendulum at most min(250, 1e5 / nv) steps.
  std::optional<double> until;
  StopToken stop;  // when it asks, Verify ends with Interrupted at its next step (default: never)
};

// A pendulum's period at several amplitudes, simulated with RK4, against the exact
// elliptic-integral period, and that exact curve densely.
struct PendulumFigures {
  struct PeriodPoint {
    double amplitude = 0;  // rad
    double period = 0;     // s, simulated
    double exact = 0;      // s
  };
  std::vector<PeriodPoint> periods;
  std::vector<PeriodPoint> exact_curve;  // period unused (NaN)
  double small_angle_period = 0;         // s, 2*pi*sqrt(I/(m*g*d))
};

// What the checks measured, kept for pictures (--report): the nominal run's curves, the
// convergence ladder, and for a pendulum its period against amplitude. A part that was not
// measured is empty.
struct VerifyFigures {
  // The nominal run (for a pendulum, the energy check's longer run of several swings),
  // sampled every timestep.
  std::vector<double> t;                  // s
  std::vector<std::string> coords;        // each hinge and slide joint, e.g. "qpos[hinge]"
  std::vector<std::vector<double>> q;     // [joint][sample], rad or m
  std::vector<std::vector<double>> qdot;  // [joint][sample], rad/s or m/s
  std::vector<double> energy;             // potential + kinetic, J
  // The convergence check's ladder (levels empty when it did not run).
  std::string convergence_metric;
  ConvergenceResult convergence;
  double expected_order = 0;
  // A single hinge pendulum's figures; empty for any other model.
  std::optional<PendulumFigures> pendulum;
};

// How long the nominal run simulated (the run that determinism, warnings, convergence and
// energy judge), and why when it is shorter than asked: a large model gets a step budget
// from its size (nv), never from the machine's speed, so the verdict stays deterministic.
struct VerifyHorizon {
  double until = 0;      // s simulated
  double requested = 0;  // s: VerifyOptions::until, or the chapter's 2 s when unset
  long steps = 0;        // of the model's timestep
  std::string why;       // empty unless shortened: "at most 250 steps for a model with nv = 18"
  bool shortened() const { return until < requested; }
};

struct VerifyReport {
  std::string model;
  // What every run started from: the reference pose's description and the assignments on
  // top, e.g. "keyframe 'home'", "qpos0 with qpos[hinge]=0.7", "qpos0 with 3 assignments".
  std::string start;
  double tol = 0;  // the tolerance the checks were judged with (VerifyOptions::tol)
  VerifyHorizon horizon;
  std::vector<CheckRow> checks;
  VerifyFigures figures;
  int Count(CheckStatus status) const;
  bool failed() const { return Count(CheckStatus::kFail) > 0; }
};

// Runs every check on `model` (not modified). Never throws for what a model does
// (divergence, warnings, non-convergence are results); @throws ValueError for options
// that make no sense (tol <= 0, an unknown keyframe) and LoadError/MujocoError from MuJoCo
// itself; Interrupted when options.stop asks.
VerifyReport Verify(const Model& model, const VerifyOptions& options);

// The assignments every run of Verify(model, options) starts from, in the order they apply: the
// reference pose's keyframe (none for qpos0), then options.sets. A report's pictures start
// there. @throws ValueError for an unknown options.keyframe.
std::vector<Assignment> VerifyStart(const Model& model, const VerifyOptions& options);

// The nominal run's horizon Verify(model, options) will judge on, known before it runs (a
// report's pictures show that run while the check runs). @throws as Verify does for a bad
// `until` or assignments the model refuses.
VerifyHorizon NominalHorizon(const Model& model, const VerifyOptions& options);

}  // namespace plumb

#endif  // PLUMB_INCLUDE_PLUMB_VERIFY_H_
