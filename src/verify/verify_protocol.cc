// The verify protocol for any model: the nominal scenario and its runs, and the checks
// load, determinism, warnings, convergence, energy and radians.

#include "verify/verify_protocol.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <optional>

#include "core/mujoco_compat.h"
#include "core/strings.h"
#include "plumb/converge.h"
#include "plumb/error.h"
#include "plumb/keyframe.h"
#include "plumb/metric.h"
#include "plumb/path.h"
#include "plumb/timing.h"

namespace plumb::verify {
namespace {

class TraceSink : public SampleSink {
 public:
  TraceSink(Trace* trace, bool energy) : trace_(trace), energy_(energy) {}
  void Begin(const std::vector<Path>&) override {}
  void Sample(const std::vector<double>& row) override {
    trace_->t.push_back(row[0]);
    std::size_t first = 1;
    if (energy_) {
      trace_->energy.push_back(row[1] + row[2]);
      trace_->kinetic.push_back(row[2]);
      trace_->ncon.push_back(static_cast<int>(row[3]));
      trace_->nefc.push_back(static_cast<int>(row[4]));
      trace_->max_ncon = std::max(trace_->max_ncon, trace_->ncon.back());
      trace_->max_nefc = std::max(trace_->max_nefc, trace_->nefc.back());
      first = 5;
    }
    std::size_t n = trace_->coords.size();
    for (std::size_t c = 0; c < n; ++c) {
      trace_->coords[c].push_back(row[first + 2 * c]);
      trace_->vels[c].push_back(row[first + 2 * c + 1]);
    }
  }

 private:
  Trace* trace_;
  bool energy_;
};

// The scenario under test: the nominal model with the user's assignments.

}  // namespace

double RelError(double measured, double reference) {
  return std::fabs(measured - reference) / std::max(std::fabs(reference), 1e-300);
}

CheckRow Row(std::string id, std::string title) {
  CheckRow r;
  r.id = std::move(id);
  r.title = std::move(title);
  return r;
}

CheckRow Skip(std::string id, std::string title, std::string why) {
  CheckRow r = Row(std::move(id), std::move(title));
  r.status = CheckStatus::kSkip;
  r.explanation = std::move(why);
  return r;
}

void SetNumbers(CheckRow* r, double measured, double reference, const char* unit,
                const char* spec) {
  r->measured.value = measured;
  r->reference.value = reference;
  r->rel_error = RelError(measured, reference);
  r->measured_text = fmt::format(fmt::runtime(spec), measured) + unit;
  r->reference_text = fmt::format(fmt::runtime(spec), reference) + unit;
  // the unit as a name: " s" -> "s"
  std::string name(unit);
  name.erase(0, name.find_first_not_of(' '));
  r->measured.unit = r->reference.unit = name;
}

std::string Seconds(double t) { return fmt::format("{:g} s", t); }

VerifyScenario::VerifyScenario(const Model& model, const VerifyOptions& options)
    : model_(model.Clone()),
      pose_(FindReferencePose(model, options.keyframe)),
      sets_(ReferenceStart(model, pose_, options.sets)),
      user_sets_(options.sets),
      start_(DescribeStart(pose_, options.sets)),
      stop_(options.stop),
      nominal_(model.Clone()) {
  asleep_ = FindSleepingStart(nominal_, pose_, options.sets);
  WakeForTesting(model_);
  WakeForTesting(nominal_);
}

const Trace& VerifyScenario::Simulate(const std::vector<Assignment>& extra, double until,
                                      bool energy) const {
  std::string key = fmt::format("{:.17g}", until);
  for (const Assignment& a : extra) key += "|" + a.text;
  auto found = memo_.find(key + "|energy");
  if (found != memo_.end()) return found->second;
  if (!energy) {
    found = memo_.find(key);
    if (found != memo_.end()) return found->second;
  }
  return memo_[energy ? key + "|energy" : key] = SimulateAnew(extra, until, energy);
}

Trace VerifyScenario::SimulateAnew(const std::vector<Assignment>& extra, double until,
                                   bool energy) const {
  Model work = model_.Clone();
  if (energy) work.get_mutable()->opt.enableflags |= mjENBL_ENERGY;
  Data data(work);
  std::vector<Assignment> all = sets_;
  all.insert(all.end(), extra.begin(), extra.end());
  ApplyAssignments(work, data, all);
  const mjModel* m = work.get();
  Trace trace;
  RunSpec spec;
  spec.until = until;
  spec.every = m->opt.timestep;
  spec.stop = stop_;
  spec.columns = {ResolvePath(work, "time")};
  if (energy) {
    for (const char* path : {"energy[0]", "energy[1]", "ncon", "nefc"}) {
      spec.columns.push_back(ResolvePath(work, path));
    }
  }
  for (int j = 0; j < m->njnt; ++j) {
    if (m->jnt_type[j] != mjJNT_HINGE && m->jnt_type[j] != mjJNT_SLIDE) continue;
    std::string name = work.Name(mjOBJ_JOINT, j);
    Path p = ResolvePath(work, "qpos[" + std::to_string(m->jnt_qposadr[j]) + "]");
    p.text = name.empty() ? p.text : "qpos[" + name + "]";
    spec.columns.push_back(p);
    spec.columns.push_back(ResolvePath(work, "qvel[" + std::to_string(m->jnt_dofadr[j]) + "]"));
    trace.coord_names.push_back(p.text);
  }
  trace.coords.resize(trace.coord_names.size());
  trace.vels.resize(trace.coord_names.size());
  TraceSink sink(&trace, energy);
  try {
    trace.result = Run(work, data, spec, sink);
  } catch (const MujocoError& e) {
    // a fatal error (an arena too small) ends this run, not the whole protocol: the checks
    // that read the run report it as a failed run
    trace.fatal = true;
    trace.result.diverged = true;
    trace.result.divergence = Divergence{};
    trace.result.divergence->reason = FatalRunProblem(work, e.what()) + ".";
  }
  const mjData* d = data.get();
  trace.final_state.assign(d->qpos, d->qpos + m->nq);
  trace.final_state.insert(trace.final_state.end(), d->qvel, d->qvel + m->nv);
  trace.final_state.insert(trace.final_state.end(), d->act, d->act + m->na);
  TakeMujocoWarnings();
  return trace;
}

// ---- load --------------------------------------------------------------------------------

CheckRow CheckLoad(const VerifyContext& ctx, CheckRow r) {
  const Model& model = ctx.model;
  const mjModel* m = model.get();
  double total = 0;
  int moving = 0;
  for (int b = 1; b < m->nbody; ++b) {
    total += m->body_mass[b];
    if (m->body_weldid[b] != 0) ++moving;
  }
  r.measured_text = fmt::format("{:.6g} kg in {} bodies", total, m->nbody - 1);
  r.measured = {total, "kg"};
  std::string bodies;
  for (int b = 1; b < m->nbody && b <= 6; ++b) {
    std::string name = model.Name(mjOBJ_BODY, b);
    bodies += fmt::format("{}{} {:.4g} kg, I = ({:.4g}, {:.4g}, {:.4g}) kg*m^2",
                          bodies.empty() ? "" : "; ", name.empty() ? "#" + std::to_string(b) : name,
                          m->body_mass[b], m->body_inertia[3 * b], m->body_inertia[3 * b + 1],
                          m->body_inertia[3 * b + 2]);
  }
  if (m->nbody > 7) bodies += fmt::format("; ... ({} more)", m->nbody - 7);
  NonFiniteValues bad = NonFiniteParameters(model);
  if (bad.total > 0) {
    r.status = CheckStatus::kFail;
    r.measured_text = fmt::format("{} NaN or infinite parameter(s)", bad.total);
    r.explanation = fmt::format(
        "the compiled model holds {}{}: MuJoCo's compiler accepts NaN and infinity with at most "
        "a warning, and such a value poisons the steps that use it. Give a finite value to the "
        "MJCF attribute that sets each one.",
        fmt::join(bad.first, ", "), bad.total > static_cast<long>(bad.first.size()) ? ", ..." : "");
  } else if (model.compile_warnings().empty()) {
    r.status = CheckStatus::kPass;
    r.explanation = fmt::format("compiled cleanly: {} moving bodies, {} dofs. As compiled: {}.",
                                moving, m->nv, bodies);
  } else {
    r.status = CheckStatus::kWarn;
    r.explanation = "MuJoCo's compiler warned: " + model.compile_warnings();
  }
  if (!ctx.s.asleep().empty()) {
    r.explanation += " " + ctx.s.asleep().Describe() +
                     ": every run here has sleep off, so the checks see their physics.";
  }
  return r;
}

// ---- start ------------------------------------------------------------------------------

namespace {

// The first issues' sentences, "; "-joined, and how many more there are.
std::string IssueTexts(const std::vector<StartIssue>& issues) {
  std::vector<std::string> texts;
  for (std::size_t i = 0; i < issues.size() && i < 5; ++i) texts.push_back(issues[i].text);
  if (issues.size() > 5) texts.push_back(fmt::format("{} more", issues.size() - 5));
  return Join(texts, "; ");
}

}  // namespace

CheckRow CheckStart(const VerifyContext& ctx, CheckRow r) {
  const VerifyScenario& s = ctx.s;
  // the state every run starts from, as the runs put it there
  Model work = s.model().Clone();
  Data data(work);
  ApplyAssignments(work, data, s.sets());
  data.Forward();
  std::vector<StartIssue> issues = StartIssues(work, data);
  TakeMujocoWarnings();
  // qpos0's joints outside their ranges, which the reference pose brought inside
  const std::vector<StartIssue>& moved = s.pose().outside;
  r.reference_text = "inside every range, no deep contact";
  if (issues.empty() && moved.empty()) {
    r.status = CheckStatus::kPass;
    r.measured_text = "inside";
    r.explanation = fmt::format(
        "{}: every limited joint starts inside its range and no contact is deeper than its "
        "solimp width",
        s.start());
    return r;
  }
  std::vector<StartIssue> all = moved;
  all.insert(all.end(), issues.begin(), issues.end());
  const StartIssue& first = all.front();
  r.status = CheckStatus::kWarn;
  r.measured_text = DescribeStartIssues(all, 1);
  r.measured = {first.value, first.unit};
  if (all.size() == 1 && first.kind == StartIssue::Kind::kJointOutsideRange) {
    r.element = {"joint", work.Name(mjOBJ_JOINT, first.id), first.id};
  }
  std::vector<std::string> parts;
  if (!moved.empty()) {
    parts.push_back(fmt::format(
        "the model has no keyframe 'home' or 'test', and its qpos0 is not a start its authors "
        "would have meant: {}. The runs start with each such joint 1% of its range inside its "
        "nearest bound, as audit's do",
        IssueTexts(moved)));
  }
  if (!issues.empty()) {
    parts.push_back(fmt::format(
        "the start ({}) is not one the model's authors would have meant: {}. A limit throws its "
        "joint back in the first steps, a deep contact pushes its geoms apart at full impedance, "
        "and every check after measures that, not the model",
        s.start(), IssueTexts(issues)));
  }
  r.explanation = Join(parts, ". ") + ".";
  r.fix = moved.empty()
              ? "start inside the ranges: a keyframe of the model, or a whole qpos or assignments "
                "that put each joint named here inside its range"
              : "give the model a keyframe 'home' its authors mean, inside every joint range";
  return r;
}

// ---- determinism -----------------------------------------------------------------------

CheckRow CheckDeterminism(const VerifyContext& ctx, CheckRow r) {
  const VerifyScenario& s = ctx.s;
  const Trace& first = ctx.trace;
  double until = ctx.until;
  Trace second = s.SimulateAnew({}, until, /*energy=*/true);
  bool same = first.final_state.size() == second.final_state.size() &&
              std::memcmp(first.final_state.data(), second.final_state.data(),
                          first.final_state.size() * sizeof(double)) == 0 &&
              first.energy.size() == second.energy.size() &&
              std::memcmp(first.energy.data(), second.energy.data(),
                          first.energy.size() * sizeof(double)) == 0;
  r.measured_text = same ? "identical" : "different";
  r.reference_text = "identical";
  r.status = same ? CheckStatus::kPass : CheckStatus::kFail;
  r.explanation = same
                      ? fmt::format("two runs of {} gave the same state and energy to the last bit",
                                    Seconds(until))
                      : "two runs from the same state differ: something non-deterministic (a "
                        "callback, uninitialised memory or threads) enters the simulation";
  return r;
}

// ---- warnings ----------------------------------------------------------------------------

CheckRow CheckWarnings(const VerifyContext& ctx, CheckRow r) {
  const Trace& nominal = ctx.trace;
  double until = ctx.until;
  r.reference_text = "none";
  if (nominal.result.diverged) {
    r.status = CheckStatus::kFail;
    r.measured_text = nominal.fatal ? "stopped by MuJoCo" : "diverged";
    r.explanation = nominal.result.divergence->reason +
                    (nominal.fatal ? ""
                                   : " Shrink the timestep and check masses and inertias (plumb "
                                     "run writes a repro).");
    return r;
  }
  if (nominal.result.warnings.empty()) {
    r.status = CheckStatus::kPass;
    r.measured_text = "none";
    r.explanation =
        fmt::format("{} of simulation raised no warning and stayed finite", Seconds(until));
    return r;
  }
  std::vector<std::string> kinds;
  for (const WarningSummary& w : nominal.result.warnings) {
    kinds.push_back(
        fmt::format("{} x{} (first at t = {:g} s: {})", w.kind, w.count, w.first_time, w.message));
  }
  r.status = CheckStatus::kWarn;
  r.measured_text = fmt::format("{} kind(s)", kinds.size());
  r.explanation =
      "MuJoCo warned: " + fmt::format("{}", fmt::join(kinds, "; ")) +
      ". A warning means results were truncated or reset; it is not a log line to ignore.";
  return r;
}

// ---- convergence -------------------------------------------------------------------------

namespace {

// The metric the convergence check follows: the pendulum's angle, or the whole state, at
// the end of the run.
std::string ConvergenceMetric(const VerifyContext& ctx) {
  const std::optional<PendulumParams>& pendulum = ctx.pendulum;
  const Model& nominal = ctx.s.Nominal();
  std::string joint = pendulum ? nominal.Name(mjOBJ_JOINT, pendulum->joint) : "";
  if (joint.empty() && pendulum) joint = std::to_string(nominal->jnt_qposadr[pendulum->joint]);
  return pendulum ? fmt::format("qpos[{}]@{:g}", joint, ctx.until)
                  : fmt::format("state@{:g}", ctx.until);
}

// Row `r` when a level diverged: the ladder starts at the model's own timestep, so any
// diverged level is a failure.
CheckRow Diverged(CheckRow r, const ConvergenceResult& c) {
  r.status = CheckStatus::kFail;
  r.measured_text = "a level diverged";
  r.explanation = c.problem;
  return r;
}

// Why the model's own timestep (level 0) is not the recommended one: its own error or
// spread, or else the first finer level that misses the tolerance.
std::string WhyNotConverged(const ConvergenceResult& c, const std::string& metric_text) {
  double target = c.tol * c.scale;
  const ConvergenceLevel& own = c.levels[0];
  auto share = [&](double v) { return fmt::format("{:.3g} ({:.2g}% of its scale {:.3g})", v,
                                                  100 * v / c.scale, c.scale); };
  if (std::isfinite(own.error) && own.error > target) {
    return fmt::format("{} at dt = {:g} s is off by {}, more than tol {:g}", metric_text, own.dt,
                       share(own.error), c.tol);
  }
  if (!LevelMeetsTolerance(own, false, target)) {
    return fmt::format("{} at dt = {:g} s differs from a finer level by {}, more than tol {:g}",
                       metric_text, own.dt, share(own.spread), c.tol);
  }
  std::size_t i = 1;
  while (i + 1 < c.levels.size() && LevelMeetsTolerance(c.levels[i], false, target)) ++i;
  const ConvergenceLevel& finer = c.levels[i];
  double miss = std::isfinite(finer.error) && finer.error > target ? finer.error : finer.spread;
  return fmt::format(
      "{} at dt = {:g} s meets tol {:g}, but the finer dt = {:g} s does not (off by {}): the "
      "estimates do not settle as dt shrinks, so no level above it is recommended",
      metric_text, own.dt, c.tol, finer.dt, share(miss));
}

// The explanation of a passing row: the error against the extrapolation where an order shows,
// else the levels' agreement.
std::string Converged(const ConvergenceResult& c, const std::string& metric_text,
                      const std::string& integrator, double expected) {
  const ConvergenceLevel& own = c.levels[0];
  if (c.estimate.resolved && std::isfinite(own.error)) {
    std::string text = fmt::format(
        "{} with {} at dt = {:g} s is within {:.2g}% of the extrapolated {:.10g}; observed "
        "order {:.2f} (expected {:g} for {}).",
        metric_text, integrator, own.dt, 100 * own.error / c.scale, c.estimate.extrapolated,
        c.estimate.order, expected, integrator);
    if (std::fabs(c.estimate.order - expected) > 0.5) {
      text += " The order differs from the integrator's.";
    }
    return text;
  }
  return fmt::format(
      "{} with {} at dt = {:g} s and every finer level agree within {:.3g} ({:.2g}% of its scale "
      "{:.3g}), inside tol {:g}: converged. The order is information, not the verdict: {}.",
      metric_text, integrator, own.dt, own.spread, 100 * own.spread / c.scale, c.scale, c.tol,
      c.estimate.note);
}

}  // namespace

CheckRow CheckConvergence(const VerifyContext& ctx, CheckRow r) {
  const VerifyScenario& s = ctx.s;
  const Trace& nominal = ctx.trace;
  double tol = ctx.tol;
  if (!nominal.kinetic.empty() &&
      *std::max_element(nominal.kinetic.begin(), nominal.kinetic.end()) == 0) {
    return Skip(r.id, r.title, "nothing moves in the nominal run: every timestep gives the same");
  }
  const mjModel* m = s.Nominal().get();
  double dt = m->opt.timestep;
  std::string metric_text = ConvergenceMetric(ctx);
  Metric metric = ParseMetric(s.model(), metric_text);
  // plumb converge's ladder (dt to dt/16) and rule, so both recommend the same timestep
  ConvergenceResult c = Converge(s.model(), s.sets(), metric, dt, 4, tol, ctx.until, s.stop());
  double expected = ExpectedOrder(m->opt.integrator);
  if (ctx.figures != nullptr) {
    ctx.figures->convergence_metric = metric_text;
    ctx.figures->convergence = c;
    ctx.figures->expected_order = expected;
  }
  if (!c.ok) return Diverged(std::move(r), c);
  std::string integrator = compat::NameOf(compat::kIntegrators, m->opt.integrator);
  bool contacts = nominal.max_ncon > 0;
  std::string notes = contacts ? " Caveat: " + ContactCaveat(nominal.max_ncon) + "." : "";
  if (!SolrefNote(c).empty()) notes += " The " + SolrefNote(c) + ".";
  const ConvergenceLevel& own = c.levels[0];  // the model's own timestep
  r.reference_text = fmt::format("tol {:g} x scale {:.3g}", tol, c.scale);
  r.reference.value = tol * c.scale;
  std::string levels;
  for (const ConvergenceLevel& l : c.levels) {
    levels += fmt::format("{}dt={:g}: {:.10g}", levels.empty() ? "" : ", ", l.dt, l.value);
  }
  bool estimated = c.estimate.resolved && std::isfinite(own.error);
  r.measured.value = estimated ? own.error : own.spread;
  r.rel_error = r.measured.value / c.scale;
  r.measured_text =
      estimated ? fmt::format("error {:.3g} at dt = {:g} s (order {:.2f})", own.error, dt,
                              c.estimate.order)
                : fmt::format("levels within {:.3g} at dt = {:g} s (no order)", own.spread, dt);
  if (c.recommended_dt == dt) {
    r.status = CheckStatus::kPass;
    r.explanation = Converged(c, metric_text, integrator, expected) + notes + " Levels " +
                    levels + ".";
    return r;
  }
  // a clean asymptotic sequence proves the error; contacts or an odd order only suggest it
  bool proven = estimated && own.error > tol * c.scale && !contacts &&
                std::fabs(c.estimate.order - expected) <= 0.5;
  r.status = proven ? CheckStatus::kFail : CheckStatus::kWarn;
  std::string advice =
      c.recommended_dt > 0
          ? fmt::format("the largest timestep that would pass, with every finer level, is {:g} s "
                        "(as plumb converge --metric '{}' --tol {:g} recommends from this start)",
                        c.recommended_dt, metric_text, tol)
          : std::string("no tested timestep passes");
  std::string order = c.estimate.resolved
                          ? fmt::format("Observed order {:.2f} (expected {:g} for {}).",
                                        c.estimate.order, expected, integrator)
                          : "No order visible: " + c.estimate.note + ".";
  r.explanation = fmt::format("not converged: {}; {}. {}{} Levels {}.",
                              WhyNotConverged(c, metric_text), advice, order, notes, levels);
  return r;
}

// ---- energy ------------------------------------------------------------------------------

namespace {

// Whether `m` sets MuJoCo's disable flag `name`, as mjDISABLESTRING spells it ("Actuation",
// "Damper"); false when this MuJoCo has no flag of that name.
bool Disabled(const mjModel* m, const char* name) {
  for (int i = 0; i < mjNDISABLE; ++i) {
    if (std::strcmp(mjDISABLESTRING[i], name) == 0) return (m->opt.disableflags & (1 << i)) != 0;
  }
  return false;
}

// Whether MuJoCo applies the joint and tendon damping, and their dry friction, of `m`
// (MuJoCo 2.x turns damping off with "Passive", 3.x with "Damper").
bool DampingActs(const mjModel* m) { return !Disabled(m, "Damper") && !Disabled(m, "Passive"); }
bool FrictionlossActs(const mjModel* m) {
  return !Disabled(m, "Frictionloss") && !Disabled(m, "Constraint");
}

// What drives the model from outside with actuation as its flags leave it, or "": an actuator
// pushing at ctrl = 0, or an assignment of a nonzero input (a keyframe's ctrl among them).
std::string Driven(const VerifyScenario& s) {
  const mjModel* m = s.Nominal().get();
  bool actuation = !Disabled(m, "Actuation");
  if (actuation) {
    std::string pushing = ActuatorPushingAtZeroControl(s.Nominal());
    if (!pushing.empty()) return pushing;
  }
  for (const Assignment& a : s.sets()) {
    bool input = (a.path.field == "ctrl" && actuation) || a.path.field == "qfrc_applied" ||
                 a.path.field == "xfrc_applied" || a.path.field == "mocap_pos";
    if (input && std::any_of(a.values.begin(), a.values.end(), [](double v) { return v != 0; }))
      return "the assignment '" + a.text + "' drives it";
  }
  return "";
}

// Why a model is not passive in the sense of the energy check whatever its run does, or "".
// Whatever the model's disable flags switch off (actuation, equality constraints, damping, dry
// friction) is not held against it.
std::string NotPassive(const VerifyScenario& s) {
  const mjModel* m = s.Nominal().get();
  if (std::string driven = Driven(s); !driven.empty()) return driven;
  if (m->neq > 0 && !Disabled(m, "Equality") && !Disabled(m, "Constraint"))
    return "it has equality constraints";
  if (m->opt.density != 0 || m->opt.viscosity != 0) return "it has fluid forces";
  for (int i = 0; i < m->ntendon; ++i) {
    if ((m->tendon_damping[i] != 0 && DampingActs(m)) ||
        (m->tendon_frictionloss[i] != 0 && FrictionlossActs(m)))
      return "it has damped tendons";
  }
  if (m->nmocap > 0) return "it has mocap bodies that can push it";
  return "";
}

// The first sample of `run` at which a contact or a joint or tendon limit acts, and what it is;
// sample -1 when none does. Past it, E omits what their soft constraints store.
struct ConstraintOnset {
  long sample = -1;
  std::string why;
};
ConstraintOnset FirstConstraint(const mjModel* m, const Trace& run) {
  // dry friction adds one constraint row per dof or tendon all the time; more rows than
  // that are joint or tendon limits at work, whose soft springs store energy E omits
  int friction_rows = 0;
  for (int i = 0; i < m->nv && FrictionlossActs(m); ++i) {
    friction_rows += m->dof_frictionloss[i] > 0;
  }
  for (int i = 0; i < m->ntendon && FrictionlossActs(m); ++i) {
    friction_rows += m->tendon_frictionloss[i] > 0;
  }
  for (std::size_t k = 0; k < run.ncon.size(); ++k) {
    if (run.ncon[k] > 0) {
      return {static_cast<long>(k),
              "contacts occur (MuJoCo's soft contacts bound energy only roughly)"};
    }
    if (run.nefc[k] > friction_rows) {
      return {static_cast<long>(k),
              "a joint or tendon limit engages (its soft constraint stores energy that E omits)"};
    }
  }
  return {};
}

// The first `samples` samples of `run`: what the energy check judges when a constraint acts
// later.
Trace Head(const Trace& run, long samples) {
  Trace head;
  auto first = [samples](const auto& v) { return std::vector(v.begin(), v.begin() + samples); };
  head.t = first(run.t);
  head.energy = first(run.energy);
  head.kinetic = first(run.kinetic);
  for (const auto& c : run.coords) head.coords.push_back(first(c));
  for (const auto& v : run.vels) head.vels.push_back(first(v));
  head.coord_names = run.coord_names;
  return head;
}

bool Dissipative(const mjModel* m) {
  for (int i = 0; i < m->nv; ++i) {
    if ((m->dof_damping[i] != 0 && DampingActs(m)) ||
        (m->dof_frictionloss[i] != 0 && FrictionlossActs(m)))
      return true;
  }
  return false;
}

// Largest rise of total energy above its running minimum.
double LargestRise(const std::vector<double>& energy) {
  double low = energy.empty() ? 0 : energy[0], rise = 0;
  for (double e : energy) {
    low = std::min(low, e);
    rise = std::max(rise, e - low);
  }
  return rise;
}

}  // namespace

namespace {

// Row `r` for a run where nothing dissipates: the relative drift of total energy is integration
// error.
CheckRow JudgeConservative(CheckRow r, const Trace& run, double until, double tol) {
  double max_kinetic = *std::max_element(run.kinetic.begin(), run.kinetic.end());
  double e0 = run.energy.front();
  auto [lo, hi] = std::minmax_element(run.energy.begin(), run.energy.end());
  double drift = std::max(std::fabs(*hi - e0), std::fabs(*lo - e0)) / max_kinetic;
  r.measured_text = fmt::format("{:.3g} of max KE", drift);
  r.reference_text = fmt::format("<= {:g}", tol);
  r.measured.value = drift;
  r.reference.value = tol;
  r.status = drift <= tol        ? CheckStatus::kPass
             : drift <= 10 * tol ? CheckStatus::kWarn
                                 : CheckStatus::kFail;
  r.explanation = fmt::format(
      "nothing dissipates energy, so E = potential + kinetic should stay at {:.6g} J; it "
      "strays by {:.3g} of the largest kinetic energy {:.4g} J over {}. A discrete integrator "
      "never conserves it exactly; a smaller timestep or RK4 shrinks the drift.",
      e0, drift, max_kinetic, Seconds(until));
  return r;
}

// Row `r` for a damped run: energy may not rise beyond the integrator's own energy wobble,
// measured on the same run with dissipation removed.
CheckRow JudgeDissipative(CheckRow r, const VerifyScenario& s, const Trace& run, double until) {
  const mjModel* m = s.Nominal().get();
  double max_kinetic = *std::max_element(run.kinetic.begin(), run.kinetic.end());
  std::vector<Assignment> undamped;
  for (int i = 0; i < m->nv; ++i) {
    undamped.push_back(s.Set(fmt::format("dof_damping[{}]=0", m->jnt_dofadr[m->dof_jntid[i]])));
    undamped.push_back(
        s.Set(fmt::format("dof_frictionloss[{}]=0", m->jnt_dofadr[m->dof_jntid[i]])));
  }
  const Trace& twin = s.Simulate(undamped, until, /*energy=*/true);
  auto [tlo, thi] = std::minmax_element(twin.energy.begin(), twin.energy.end());
  double wobble = *thi - *tlo;
  double rise = LargestRise(run.energy);
  double allowed = 1.5 * wobble + 1e-12 * max_kinetic;
  // the peak envelope of a lone hinge/slide coordinate falls (single samples need not);
  // coupled coordinates trade energy, so one of them may swing higher for a while
  std::string envelope;
  bool envelope_ok = true;
  for (std::size_t c = 0; c < run.coords.size() && m->nv == 1; ++c) {
    std::vector<double> peaks = Peaks(run.coords[c]);
    if (peaks.size() < 2) continue;
    bool falling = true;
    for (std::size_t k = 1; k < peaks.size(); ++k) falling = falling && peaks[k] < peaks[k - 1];
    envelope_ok = envelope_ok && falling;
    envelope += fmt::format("{}{}: {} peaks {} ({:.5g} -> {:.5g})", envelope.empty() ? "" : "; ",
                            run.coord_names[c], peaks.size(), falling ? "fall" : "DO NOT fall",
                            peaks.front(), peaks.back());
  }
  r.measured_text = fmt::format("largest rise {:.3g} J", rise);
  r.reference_text = fmt::format("<= {:.3g} J", allowed);
  r.measured = {rise, "J"};
  r.reference = {allowed, "J"};
  r.status = rise <= allowed && envelope_ok ? CheckStatus::kPass : CheckStatus::kFail;
  std::string peaks = m->nv > 1          ? "Peaks are not compared: the coordinates are coupled."
                      : envelope.empty() ? "The coordinate did not swing twice to compare peaks."
                                         : "Peak envelope: " + envelope + ".";
  r.explanation = fmt::format(
      "damping only removes energy: E went from {:.6g} J to {:.6g} J over {}; its largest rise "
      "{:.3g} J {} the integrator's own wobble allowance ({:.3g} J, from the undamped twin). {}",
      run.energy.front(), run.energy.back(), Seconds(until), rise,
      rise <= allowed ? "stays within" : "EXCEEDS", allowed, peaks);
  return r;
}

// What the model's disable flags take out of the energy balance, for the row's explanation.
std::string DisabledNote(const mjModel* m) {
  std::vector<std::string> off;
  if (m->nu > 0 && Disabled(m, "Actuation")) {
    off.push_back("actuation (its actuators exert nothing)");
  }
  if (Disabled(m, "Gravity")) off.push_back("gravity (no potential energy of height)");
  if (!DampingActs(m)) off.push_back("damping");
  if (off.empty()) return "";
  return " The model's opt.disableflags switch off " + Join(off, ", ") + ".";
}

}  // namespace

CheckRow CheckEnergy(const VerifyContext& ctx, CheckRow r) {
  const VerifyScenario& s = ctx.s;
  const Trace& nominal = ctx.energy_trace;
  const mjModel* m = s.Nominal().get();
  if (nominal.result.diverged) return Skip(r.id, r.title, "the nominal run diverged");
  std::string why = NotPassive(s);
  if (!why.empty()) return Skip(r.id, r.title, "no energy bound applies: " + why);
  // before a contact or a limit acts, the run is a plain passive system: judge that part when
  // it is at least a quarter of the run
  ConstraintOnset onset = FirstConstraint(m, nominal);
  long samples = static_cast<long>(nominal.t.size());
  if (onset.sample >= 0 && onset.sample < samples / 4) {
    return Skip(r.id, r.title, "no energy bound applies: " + onset.why);
  }
  std::optional<Trace> head;
  if (onset.sample >= 0) head = Head(nominal, onset.sample);
  const Trace& run = head ? *head : nominal;
  double until = head ? (onset.sample - 1) * m->opt.timestep : ctx.energy_until;
  double max_kinetic = *std::max_element(run.kinetic.begin(), run.kinetic.end());
  if (max_kinetic <= 0) return Skip(r.id, r.title, "nothing moves in the nominal run");
  r = Dissipative(m) ? JudgeDissipative(std::move(r), s, run, until)
                     : JudgeConservative(std::move(r), run, until, ctx.tol);
  if (head) {
    r.explanation +=
        fmt::format(" Judged on the first {} of the {} run: at t = {:g} s {}.", Seconds(until),
                    Seconds(ctx.energy_until), nominal.t[onset.sample], onset.why);
  }
  r.explanation += DisabledNote(m);
  return r;
}

CheckRow ExerciseRadians(const VerifyContext& ctx, CheckRow r) {
  const VerifyScenario& s = ctx.s;
  const mjModel* m = s.model().get();
  std::vector<std::string> seen;
  bool suspicious = false;
  for (const Assignment& a : s.user_sets()) {
    if (a.path.field != "qpos") continue;
    for (long k = 0; k < a.path.count; ++k) {
      long adr = a.path.first + k;
      for (int j = 0; j < m->njnt; ++j) {
        if (m->jnt_type[j] != mjJNT_HINGE || m->jnt_qposadr[j] != adr) continue;
        double v = a.values[k];
        bool big = std::fabs(v) > 2 * M_PI;
        suspicious = suspicious || big;
        seen.push_back(
            big ? fmt::format("{} = {:g} rad is {:.2f} turns: if you meant {:g} "
                              "degrees, write {:.6g}",
                              a.path.text, v, std::fabs(v) / (2 * M_PI), v, v * M_PI / 180)
                : fmt::format("{} = {:g} rad = {:.1f} degrees", a.path.text, v, v * 180 / M_PI));
      }
    }
  }
  if (seen.empty()) return Skip(r.id, r.title, "no hinge angle was set by an assignment");
  r.status = suspicious ? CheckStatus::kWarn : CheckStatus::kPass;
  r.measured_text = suspicious ? "looks like degrees" : "plausible radians";
  r.reference_text = "|angle| <= 2*pi";
  r.explanation = fmt::format(
      "{}. MuJoCo's C API uses radians whatever the MJCF <compiler angle> "
      "says.",
      fmt::join(seen, "; "));
  return r;
}

}  // namespace plumb::verify
