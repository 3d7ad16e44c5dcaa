// plumb verify: the chapter's credibility protocol as a table of checks. Each check is
// written once, as {id, title, what it needs, function}; the checks for any model are in
// verify_protocol.cc (convergence in verify_convergence.cc, energy in verify_energy.cc),
// those for a single hinge pendulum in verify_pendulum.cc.

#include "plumb/verify.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "plumb/error.h"
#include "plumb/keyframe.h"
#include "plumb/timing.h"
#include "verify/verify_protocol.h"

namespace plumb {
namespace {

// What a check needs to run; otherwise it is a SKIP row saying why.
enum class Needs {
  kModel,      // nothing: it always runs
  kFiniteRun,  // a nominal run that did not diverge
  kPendulum,   // a single hinge pendulum under gravity, and a run that did not diverge
};

struct Check {
  const char* id;
  const char* title;
  Needs needs;
  verify::CheckFunction run;
  bool judges_nominal_run = false;  // on the nominal run's horizon (VerifyHorizon)
};

// The protocol, in report order.
constexpr Check kChecks[] = {
    {"load", "the model compiles without warnings", Needs::kModel, verify::CheckLoad},
    {"start", "the start is within every joint range, no deep contact", Needs::kModel,
     verify::CheckStart},
    {"determinism", "the same run twice is bit-identical", Needs::kModel, verify::CheckDeterminism,
     true},
    {"warnings", "no MuJoCo warning and no divergence in the nominal run", Needs::kModel,
     verify::CheckWarnings, true},
    {"convergence", "the result converges as the timestep shrinks", Needs::kFiniteRun,
     verify::CheckConvergence, true},
    {"energy", "total energy is conserved, or only decreases when damped", Needs::kModel,
     verify::CheckEnergy, true},
    {"analytic.period", "simulated period = exact large-angle period (elliptic integral)",
     Needs::kPendulum, verify::CheckAnalyticPeriod},
    {"analytic.model_settings", "the period with the model's own integrator and timestep",
     Needs::kPendulum, verify::CheckModelPeriod},
    {"analytic.damping", "the motion matches the damping classification", Needs::kPendulum,
     verify::CheckDamping},
    {"experiment.A", "initial angle 0.1, 0.7, 2.8 rad: period grows with amplitude",
     Needs::kPendulum, verify::ExperimentAmplitude},
    {"experiment.B", "damping 0, 0.05, 1.0: energy conserved vs. decaying", Needs::kPendulum,
     verify::ExperimentDamping},
    {"experiment.C", "timestep 0.0005, 0.002, 0.02 s: q at 2 s converges", Needs::kPendulum,
     verify::ExperimentTimestep},
    {"exercise.moon_gravity", "gravity -1.62 m/s^2 stretches the period by sqrt(9.81/1.62)",
     Needs::kPendulum, verify::ExerciseMoon},
    {"exercise.density", "density instead of mass: mass = density x volume", Needs::kPendulum,
     verify::ExerciseDensity},
    {"exercise.radians", "initial angles are radians at run time", Needs::kModel,
     verify::ExerciseRadians},
};

// The nominal run length: 2 s like the chapter; for other models at most 250 steps and at
// most 1e5 / nv steps (the convergence ladder runs ~16 times as many), always a whole number
// of steps, so every level of the ladder (dt to dt/16) lands on it exactly. @throws ValueError
// for a bad --until.
VerifyHorizon NominalLength(const VerifyOptions& options, const mjModel* m, double dt,
                            bool pendulum) {
  if (options.until && !(*options.until > 0 && std::isfinite(*options.until))) {
    // a run of zero steps would pass determinism and warnings without testing anything
    throw ArgumentError("until", fmt::format("{:g}", *options.until),
                        "the nominal run length must be a positive number of seconds (a run of "
                        "zero steps checks nothing).");
  }
  VerifyHorizon h;
  h.requested = options.until ? *options.until : 2.0;
  double max_steps =
      std::max(20.0, std::min(250.0, std::floor(1e5 / std::max(1.0, static_cast<double>(m->nv)))));
  double until = options.until || pendulum ? h.requested : std::min(2.0, max_steps * dt);
  if (options.until) {
    // the convergence ladder's finest level (dt / 16) takes the most steps
    RequireStepsToReach(*options.until, dt / 16, "until", "",
                        "the timestep of the convergence ladder's finest level, dt / 16");
    // the convergence ladder's coarsest level is the model's own timestep
    RequireWholeSteps(*options.until, dt, "until", fmt::format("{:g}", *options.until),
                      "the timestep: the convergence ladder's coarsest level");
  }
  h.until = std::max(dt, std::round(until / dt) * dt);
  h.steps = std::lround(h.until / dt);
  if (h.shortened()) {
    h.why = fmt::format("verify's step budget for a model with nv = {1} is {0:g} steps", max_steps,
                        m->nv);
  }
  return h;
}

// Appended to a row the nominal run judged, when that run is shorter than asked.
void SayShortHorizon(const VerifyHorizon& h, CheckRow& row) {
  if (!h.shortened() || row.status == CheckStatus::kSkip) return;
  row.explanation += fmt::format(
      " Judged on {:g} s simulated ({} steps), not {:g} s: {}; an until of {:g} s, given, judges "
      "longer.",
      h.until, h.steps, h.requested, h.why, h.requested);
}

}  // namespace

int VerifyReport::Count(CheckStatus status) const { return CountStatus(checks, status); }

std::vector<Assignment> VerifyStart(const Model& model, const VerifyOptions& options) {
  return ReferenceStart(model, FindReferencePose(model, options.keyframe), options.sets);
}

VerifyHorizon NominalHorizon(const Model& model, const VerifyOptions& options) {
  verify::VerifyScenario s(model, options);
  std::string why_not;
  bool pendulum = DetectPendulum(s.Nominal(), &why_not).has_value();
  return NominalLength(options, s.Nominal().get(), RunTimestep(model, s.sets()), pendulum);
}

VerifyReport Verify(const Model& model, const VerifyOptions& options) {
  if (!(options.tol > 0 && std::isfinite(options.tol))) {
    throw ArgumentError("tol", fmt::format("{:g}", options.tol),
                        "the relative tolerance must be positive and finite.");
  }
  VerifyReport report;
  report.model = model.file();
  report.tol = options.tol;
  verify::VerifyScenario s(model, options);
  report.start = s.start();
  const Model& nominal = s.Nominal();
  const mjModel* m = nominal.get();
  std::string why_not;
  std::optional<PendulumParams> pendulum = DetectPendulum(nominal, &why_not);
  double dt = RunTimestep(model, s.sets());
  report.horizon = NominalLength(options, m, dt, pendulum.has_value());
  double until = report.horizon.until;
  const verify::Trace& trace = s.Simulate({}, until, /*energy=*/true);
  bool finite = !trace.result.diverged;
  // a pendulum's energy check watches several swings, so peaks can be compared
  const verify::Trace* energy_trace = &trace;
  double energy_until = until;
  if (pendulum && finite) {
    double want = std::ceil(3.5 * SmallAnglePeriod(*pendulum) / dt) * dt;
    if (want > until) {
      energy_until = want;
      energy_trace = &s.Simulate({}, want, /*energy=*/true);
    }
  }
  verify::VerifyContext c{s,     model,         nominal,      pendulum,   trace,
                          until, *energy_trace, energy_until, options.tol};
  c.figures = &report.figures;
  if (pendulum && finite) {
    // a single hinge: its qpos and dof address are the same index
    c.dof = m->jnt_qposadr[pendulum->joint];
    c.theta0 = trace.coords[0].front();
  }
  std::string not_finite =
      trace.fatal ? "MuJoCo stopped the nominal run (see warnings)" : "the nominal run diverged";
  std::string not_pendulum =
      pendulum ? not_finite : "not a single hinge pendulum under gravity: " + why_not;
  for (const Check& check : kChecks) {
    if (check.needs == Needs::kFiniteRun && !finite) {
      report.checks.push_back(verify::Skip(check.id, check.title, not_finite));
    } else if (check.needs == Needs::kPendulum && !(pendulum && finite)) {
      report.checks.push_back(verify::Skip(check.id, check.title, not_pendulum));
    } else {
      report.checks.push_back(check.run(c, verify::Row(check.id, check.title)));
      if (check.judges_nominal_run) SayShortHorizon(report.horizon, report.checks.back());
    }
  }
  VerifyFigures& f = report.figures;
  f.t = energy_trace->t;
  f.coords = energy_trace->coord_names;
  f.q = energy_trace->coords;
  f.qdot = energy_trace->vels;
  f.energy = energy_trace->energy;
  return report;
}

}  // namespace plumb
