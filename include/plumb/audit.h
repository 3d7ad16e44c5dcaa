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

#ifndef PLUMB_INCLUDE_PLUMB_AUDIT_H_
#define PLUMB_INCLUDE_PLUMB_AUDIT_H_

#include <optional>
#include <string>
#include <vector>

#include "plumb/model.h"
#include "plumb/path.h"
#include "plumb/run.h"
#include "plumb/verify.h"

namespace plumb {

struct Finding {
  std::string layer;    // structure, inertia, actuator, contact, behaviour, warnings
  std::string check;    // e.g. "inertia.tiny_mass"
  std::string element;  // e.g. "body 'hand' (id 3)"; "" for the whole model
  // the same, split, when the row is about one element (else "", "", -1)
  std::string element_type;  // "body", "joint", "actuator", "geom", ...
  std::string element_name;  // "" when unnamed
  int element_id = -1;
  std::string measured;   // with units
  std::string threshold;  // with units; "" for informational rows
  CheckStatus status = CheckStatus::kPass;
  std::string fix;  // what to do about it (or what the row shows, for PASS)
};

// A control schedule for one actuator in a scenario: u(t) in ctrl units.
struct ControlSchedule {
  std::string actuator;  // actuator name
  int id = -1;
  std::string type;                                // constant, step, ramp, sine
  double value = 0;                                // constant: u; step: u after `at`; sine: offset
  double before = 0;                               // step: u before `at`; ramp: u at `start`
  double at = 0;                                   // step: switch time, s
  double start = 0, end = 0, to = 0;               // ramp: from `before` at start to `to` at end
  double amplitude = 0, frequency = 0, phase = 0;  // sine, Hz and rad
  double At(double t) const;
};

// An assertion on paths over a time window, e.g. "xpos[torso][2] > 0.8 during [0, 2]"
// or "maxabs(qvel[*]) < 50".
struct Assertion {
  std::string text;
  std::string reduce;       // "" (every sample), maxabs, min, max, final
  std::vector<Path> paths;  // every path must satisfy it ('*' expanded)
  std::string op;           // <, <=, >, >=
  double bound = 0;
  double from = 0, to = -1;  // window in s; to < 0 means the end of the run
};

// A user's behaviour scenario (JSON or TOML; see README "Scenarios").
struct Scenario {
  std::string file;
  std::string name;
  double duration = 2;              // s
  int keyframe = -1;                // keyframe to start from, -1: qpos0
  std::vector<Assignment> initial;  // state / parameter assignments after the keyframe
  std::vector<ControlSchedule> controls;
  std::vector<Assertion> assertions;
};

// Parses one assertion. @throws ValueError / PathError quoting it.
Assertion ParseAssertion(const Model& model, const std::string& text);

// Reads a scenario from a .json or .toml file. @throws ValueError naming the file and
// the entry at fault, IoError when it cannot be read.
Scenario LoadScenario(const Model& model, const std::string& file);

struct AuditOptions {
  std::vector<Assignment> sets;  // applied before everything
  // The keyframe of the reference pose, by name (--keyframe); empty: keyframe "home" or
  // "test" when the model has one, else qpos0. A scenario's own keyframe still decides
  // where that scenario starts.
  std::string keyframe;
  std::optional<Scenario> scenario;
  std::string repro_dir;          // where a diverged run's repro goes ("" = none)
  std::vector<std::string> argv;  // the command line, for the repro folder
};

struct AuditReport {
  std::string model;
  std::vector<Finding> findings;
  std::vector<std::string> repro_folders;  // written for diverged runs
  int Count(CheckStatus status) const;
};

// Audits `model` (not modified). @throws only for bad options; what the model does is
// reported as findings.
AuditReport Audit(const Model& model, const AuditOptions& options);

}  // namespace plumb

#endif  // PLUMB_INCLUDE_PLUMB_AUDIT_H_
