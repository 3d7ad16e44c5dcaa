// The verify protocol for any model: the nominal scenario and its runs, and the checks
// load, start, determinism, warnings and radians (convergence is in verify_convergence.cc,
// energy in verify_energy.cc).

#include "verify/verify_protocol.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <optional>

#include "core/mujoco_compat.h"
#include "core/strings.h"
#include "plumb/error.h"
#include "plumb/keyframe.h"
#include "plumb/path.h"
#include "plumb/timing.h"

namespace plumb::verify {
using internal::Join;

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
  std::vector<StartIssue> moved = MovedIntoRange(work, data, s.pose());
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
        DescribeStartIssues(moved, 3)));
  }
  if (!issues.empty()) {
    parts.push_back(fmt::format(
        "the start ({}) is not one the model's authors would have meant: {}. A limit throws its "
        "joint back in the first steps, a deep contact pushes its geoms apart at full impedance, "
        "and every check after measures that, not the model",
        s.start(), DescribeStartIssues(issues, 3)));
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

// ---- radians -----------------------------------------------------------------------------

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
