// Audit layer 5, behaviour: the passive settle and a run under smoothed control noise stay
// finite with bounded energy, and the user's scenario does what its assertions say.

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "audit/audit_layers.h"
#include "core/mujoco_compat.h"
#include "plumb/timing.h"
#include "scenario/assertion_tally.h"

namespace plumb::audit {
using internal::AssertionTally;

namespace {

constexpr const char* L = "behaviour";

// A run is bounded when its total energy stays within `allowed_rise` x max(1 J, |E0|)
// above where it started: a passive run has no energy source, a driven one does.
CheckRow RunFinding(const char* check, const std::string& what, const Observed& o,
                    double allowed_rise) {
  if (o.result.diverged) {
    return Make(L, check, what, "diverged", "stays finite", CheckStatus::kFail, DivergedFix(o));
  }
  double scale = std::max(1.0, std::fabs(o.energy0));
  double rise = (o.energy_max - o.energy0) / scale;
  CheckStatus status = rise > 20 * allowed_rise ? CheckStatus::kFail
                       : rise > allowed_rise    ? CheckStatus::kWarn
                                                : CheckStatus::kPass;
  // as numbers: the peak energy against the highest it may reach
  return WithNumbers(
      Make(
          L, check, what,
          fmt::format("{:g} s, energy {:.4g} -> max {:.4g} J", o.duration, o.energy0, o.energy_max),
          fmt::format("no NaN; energy rise <= {:g} x max(1 J, |E0|)", allowed_rise), status,
          status == CheckStatus::kPass
              ? "stays finite and bounded"
              : "energy grows without a matching source: check contact parameters, the "
                "timestep and actuator gains"),
      {o.energy_max, "J"}, {o.energy0 + allowed_rise * scale, "J"});
}

// Smoothed Halton noise within half of each ctrlrange, as MuJoCo's testspeed and
// Menagerie's tests drive a model.
void ControlNoise(const Model& model, const std::vector<Assignment>& sets, const ReferencePose& ref,
                  const AuditOptions& options, std::vector<Observed>* runs,
                  std::vector<CheckRow>* out) {
  const mjModel* m = model.get();
  auto control = [m](mjData* d, double t) {
    long k = static_cast<long>(t / 0.1);
    static constexpr int kPrimes[] = {2, 3, 5, 7, 11, 13, 17, 19, 23, 29, 31, 37};
    for (int i = 0; i < m->nu; ++i) {
      double h = mju_Halton(static_cast<int>(k + 1), kPrimes[i % 12]) * 2 - 1;
      double lo = m->actuator_ctrllimited[i] ? m->actuator_ctrlrange[2 * i] : -1;
      double hi = m->actuator_ctrllimited[i] ? m->actuator_ctrlrange[2 * i + 1] : 1;
      double target = 0.5 * (lo + hi) + 0.5 * (hi - lo) * 0.5 * h;
      d->ctrl[i] += 0.05 * (target - d->ctrl[i]);  // smoothed
    }
  };
  runs->push_back(Observe(model, sets, ref, Duration(m, 2.0), control, options, "control noise"));
  // actuators feed energy in: only a runaway counts
  out->push_back(RunFinding("behaviour.control_noise",
                            "smoothed Halton noise at half of each ctrlrange", runs->back(), 50));
}

// The user's scenario: from its keyframe (else the reference pose) with --set and then its
// initial assignments, under its control schedules; every assertion judged on every one
// of its paths at every step.
void RunScenario(const Model& model, const std::vector<Assignment>& sets, const ReferencePose& ref,
                 const Scenario& sc, const AuditOptions& options, std::vector<Observed>* runs,
                 std::vector<CheckRow>* out) {
  const mjModel* m = model.get();
  ReferencePose start = ref;
  if (sc.keyframe >= 0) {
    start.keyframe = sc.keyframe;
    start.description = "keyframe " + model.Name(mjOBJ_KEY, sc.keyframe);
  }
  // the user's --set first, then the scenario's initial state on top
  std::vector<Assignment> all = sets;
  all.insert(all.end(), sc.initial.begin(), sc.initial.end());
  AssertionTally tally(sc.assertions);
  Model work = model.Clone();
  Data data(work);
  StartAtPose(work, data, start, all);
  RunSpec spec;
  spec.stop = options.stop;
  spec.until = StepsToReach(sc.duration, m->opt.timestep) * m->opt.timestep;
  spec.every = m->opt.timestep;
  spec.before_step = [&](mjData* d, long) {
    for (const ControlSchedule& c : sc.controls) {
      d->ctrl[compat::ActuatorControls(m, c.id).first] = c.At(d->time);  // a pid's: its position
    }
  };
  data.Forward();
  tally.Sample(work, data, data->time);
  DerivedRefresher refresh(work);
  spec.after_step = [&](const mjData* d, long) {
    refresh(data);
    tally.Sample(work, data, d->time);
  };
  NullSink sink;
  Observed run;
  run.label = "scenario " + sc.name;
  run.duration = spec.until;
  run.result = Run(work, data, spec, sink);
  TakeMujocoWarnings();  // counted in the run's result, reported in the warnings layer
  run.repro = KeepDiverged(work, run.result, options, "scenario " + sc.file);
  runs->push_back(run);
  if (run.result.diverged) {
    out->push_back(Make(L, "behaviour.scenario", sc.name, "diverged", "stays finite",
                        CheckStatus::kFail, DivergedFix(run)));
    return;
  }
  for (std::size_t a = 0; a < sc.assertions.size(); ++a) {
    const Assertion& as = sc.assertions[a];
    AssertionTally::Verdict verdict = tally.Judge(a);
    out->push_back(Make(L, "behaviour.assertion", sc.name + ": " + as.text, verdict.measured,
                        fmt::format("{} {:g}", ComparisonName(as.op), as.bound),
                        verdict.ok ? CheckStatus::kPass : CheckStatus::kFail,
                        verdict.ok ? "the scenario's assertion holds"
                                   : "the scenario's assertion fails: the model does not do "
                                     "what the scenario expects"));
  }
}

}  // namespace

void BehaviourLayer(const Model& model, const std::vector<Assignment>& sets,
                    const ReferencePose& ref, const Observed& settle, const AuditOptions& options,
                    std::vector<Observed>* runs, std::vector<CheckRow>* out) {
  out->push_back(
      RunFinding("behaviour.passive_settle", "zero control from " + ref.description, settle, 0.5));
  if (model->nu > 0) ControlNoise(model, sets, ref, options, runs, out);
  if (options.scenario) RunScenario(model, sets, ref, *options.scenario, options, runs, out);
}

}  // namespace plumb::audit
