// plumb audit: the five layers of model acceptance, after the chapter's section 1.3.5
// (structure, inertia, actuator, contact, behaviour; each in its own audit_<layer>.cc),
// plus every MuJoCo warning raised on the way.

#include "plumb/audit.h"

#include <fmt/format.h>

#include <algorithm>

#include "audit/audit_layers.h"
#include "core/strings.h"
#include "plumb/keyframe.h"
#include "plumb/sleep.h"
#include "plumb/timing.h"

namespace plumb {
using internal::Join;

namespace {

// Every MuJoCo warning raised on the way, with the run that raised it.
void Warnings(const std::vector<audit::Observed>& runs, AuditReport* report) {
  bool any = false;
  for (const audit::Observed& o : runs) {
    for (const WarningSummary& w : o.result.warnings) {
      any = true;
      report->findings.push_back(audit::Make(
          "warnings", "warnings.mujoco", w.kind,
          fmt::format("x{} in the {}, first at t = {:g} s", w.count, o.label, w.first_time), "none",
          CheckStatus::kWarn, w.message + (o.repro.empty() ? "" : " Repro folder: " + o.repro)));
    }
    if (!o.repro.empty()) report->repro_folders.push_back(o.repro);
  }
  if (!any) {
    report->findings.push_back(audit::Make("warnings", "warnings.mujoco", "", "none", "none",
                                           CheckStatus::kPass,
                                           "no MuJoCo warning in any audit run"));
  }
}

}  // namespace

int AuditReport::Count(CheckStatus status) const { return CountStatus(findings, status); }

bool AuditReport::Failed(bool strict) const {
  // accepted findings fail nothing; a stale accept entry is a WARN of its own
  return CountUnaccepted(findings, CheckStatus::kFail) > 0 ||
         (strict && CountUnaccepted(findings, CheckStatus::kWarn) > 0);
}

std::vector<Assignment> AuditStart(const Model& model, const AuditOptions& options) {
  return ReferenceStart(model, FindReferencePose(model, options.keyframe), options.sets);
}

AuditReport Audit(const Model& loaded, const AuditOptions& options) {
  AuditReport report;
  report.model = loaded.file();
  // the reference pose (plumb/keyframe.h), then the user's --set, state assignments included
  ReferencePose ref = FindReferencePose(loaded, options.keyframe);
  report.start = DescribeStart(ref, options.sets);
  Model probe = loaded.Clone();
  SleepingStart asleep = FindSleepingStart(probe, ref, options.sets);
  // every run tests the physics with sleep off (plumb/sleep.h)
  Model model = loaded.Clone();
  WakeForTesting(model);
  Model nominal = model.Clone();
  Data data(nominal);
  StartAtPose(nominal, data, ref, options.sets);
  TakeMujocoWarnings();

  std::vector<audit::Observed> runs;
  audit::StructureLayer(nominal, &report.findings);
  audit::StartRows(nominal, data, ref, report.start, &report.findings);
  if (!asleep.empty()) {
    report.findings.push_back(audit::Make(
        "structure", "structure.sleep", Join(asleep.bodies, ", "),
        fmt::format("{} asleep", asleep.bodies.size()), "", CheckStatus::kPass,
        asleep.Describe() +
            ": the audit runs them awake (sleep off), so its rows judge their physics; a run "
            "with sleep on leaves them still until something touches them"));
  }
  audit::InertiaLayer(model, nominal, data, &report.findings);
  audit::ActuatorLayer(model, nominal, data, options.sets, ref, options, &runs, &report.findings);

  const mjModel* m = nominal.get();
  // the settle goes on past 2 s (up to 10 s, within 2.5 run budgets) until at rest
  audit::Observed settle =
      audit::Observe(model, options.sets, ref, audit::Duration(m, 2.0), nullptr, options,
                     "passive settle", audit::Duration(m, 10.0, 2.5 * audit::kDofStepBudget));
  runs.push_back(settle);
  audit::ContactLayer(nominal, settle, &report.findings);
  audit::BehaviourLayer(nominal, options.sets, ref, settle, options, &runs, &report.findings);
  Warnings(runs, &report);
  for (audit::Observed& run : runs) {
    if (run.label.rfind("step response", 0) == 0) {
      for (AuditCurve& c : run.curves) report.step_responses.push_back(std::move(c));
    }
  }
  report.settle = std::move(settle.curves);
  return report;
}

}  // namespace plumb
