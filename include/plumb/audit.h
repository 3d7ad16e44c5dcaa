// plumb audit: the five layers of model acceptance (structure, inertia, actuator,
// contact, behaviour) and every MuJoCo warning raised on the way.
//
// Each finding names the layer, the check, the element (by name and id), the measured
// value, the threshold, a status and the fix a MuJoCo expert would suggest.
//
// Example:
//   plumb::AuditOptions options;
//   options.scenario = plumb::LoadScenario(model, "stand.toml");
//   plumb::AuditReport report = plumb::Audit(model, options);
//   report.Count(plumb::CheckStatus::kFail)
//
// Thread-safety: Audit only reads `model` (every run uses a copy of its own) and starts no
// threads, so audits may run at once from several threads, also on one Model; keep_diverged is
// called on the calling thread. Each call takes (and drops) the calling thread's pending MuJoCo
// warnings (TakeMujocoWarnings).

#ifndef PLUMB_INCLUDE_PLUMB_AUDIT_H_
#define PLUMB_INCLUDE_PLUMB_AUDIT_H_

#include <cmath>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "plumb/check.h"
#include "plumb/model.h"
#include "plumb/path.h"
#include "plumb/run.h"
#include "plumb/scenario.h"

namespace plumb {

struct AuditOptions {
  std::vector<Assignment> sets;  // applied before everything
  // The keyframe of the reference pose, by name (--keyframe); empty: keyframe "home" or
  // "test" when the model has one, else qpos0. A scenario's own keyframe still decides
  // where that scenario starts.
  std::string keyframe;
  std::optional<Scenario> scenario;
  // Called with each audit run that diverged: the model as it ran (--set applied), the run
  // and what it was ("the audit run that diverged: passive settle"). It returns where it
  // kept the run ("" for nowhere), which the findings quote; the app writes repro folders
  // here (plumb::WriteRepro), the audit itself writes nothing.
  std::function<std::string(const Model& model, const RunResult& run, const std::string& what)>
      keep_diverged;
  StopToken stop;  // when it asks, Audit ends with Interrupted at its next step (default: never)
};

// One curve of an audit run, kept for pictures (--report).
struct AuditCurve {
  std::string label;     // the run: "passive settle", "step response of actuator 'elbow' (id 3)"
  std::string quantity;  // what y is, with its unit: "total energy (J)"
  std::vector<double> t;  // s, every step
  std::vector<double> y;
  double start = NAN;   // a step response's value before the step
  double target = NAN;  // a servo's setpoint after the step; NaN when it has none
};

struct AuditReport {
  std::string model;
  // The start every check is judged from (DescribeStart): "keyframe 'home'", "qpos0",
  // "qpos0 with qpos[thj0]=0.5".
  std::string start;
  // One row per finding, in layer order; each row's section is its layer: structure, inertia,
  // actuator, contact, behaviour, warnings.
  std::vector<CheckRow> findings;
  // The step responses measured (at most 12 actuators) and the passive settle's total
  // energy and fastest joint speed, step by step.
  std::vector<AuditCurve> step_responses;
  std::vector<AuditCurve> settle;
  std::vector<std::string> repro_folders;  // what keep_diverged returned, in run order
  int Count(CheckStatus status) const;
  // Whether the audit fails: a FAIL that no accept list accepts, or with `strict` a WARN.
  bool Failed(bool strict) const;
};

// The pose Audit judges `model` in, as assignments (what a report's pictures start from): the
// reference pose's keyframe (FindReferencePose with options.keyframe; none for qpos0), then
// options.sets. @throws ValueError for an unknown keyframe.
std::vector<Assignment> AuditStart(const Model& model, const AuditOptions& options);

// Audits `model` (not modified). @throws only for bad options (ValueError for an unknown
// keyframe, ValueError / PathError for a --set the model refuses), Interrupted when options.stop
// asks, MujocoError from MuJoCo and what keep_diverged throws; what the model does is reported
// as findings.
AuditReport Audit(const Model& model, const AuditOptions& options);

}  // namespace plumb

#endif  // PLUMB_INCLUDE_PLUMB_AUDIT_H_
