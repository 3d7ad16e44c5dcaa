// The scenario language of plumb audit: a start state, control schedules and assertions on
// paths over time windows, read from a JSON or TOML file (see docs/audit.md, "Scenarios are JSON or
// TOML").
//
// Example:
//   plumb::Scenario sc = plumb::LoadScenario(model, "stand.toml");
//   plumb::Assertion a = plumb::ParseAssertion(model, "xpos[torso][2] > 0.8 during [0, 2]");
//
// Thread-safety: the functions keep no state and only read `model`: they may be called from
// several threads at once, also on one Model.

#ifndef PLUMB_INCLUDE_PLUMB_SCENARIO_H_
#define PLUMB_INCLUDE_PLUMB_SCENARIO_H_

#include <string>
#include <vector>

#include "plumb/model.h"
#include "plumb/path.h"

namespace plumb {

// The shape of a control schedule.
enum class ControlShape { kConstant, kStep, kRamp, kSine };

// "constant", "step", "ramp", "sine".
const char* ControlShapeName(ControlShape shape);

// A control schedule for one actuator in a scenario: u(t) in ctrl units.
struct ControlSchedule {
  std::string actuator;  // actuator name
  int id = -1;
  ControlShape type = ControlShape::kConstant;
  double value = 0;                                // constant: u; step: u after `at`; sine: offset
  double before = 0;                               // step: u before `at`; ramp: u at `start`
  double at = 0;                                   // step: switch time, s
  double start = 0, end = 0, to = 0;               // ramp: from `before` at start to `to` at end
  double amplitude = 0, frequency = 0, phase = 0;  // sine, Hz and rad
  double At(double t) const;
};

// How an assertion reduces its samples over the window: kEach tests every sample; kMean is
// the samples' average (of a 0/1 signal: the fraction of samples where it is 1).
enum class Reduction { kEach, kMaxAbs, kMax, kMin, kFinal, kMean };

// "" for kEach, else "maxabs", "max", "min", "final", "mean".
const char* ReductionName(Reduction reduce);

enum class Comparison { kLess, kLessEqual, kGreater, kGreaterEqual };

// "<", "<=", ">", ">=".
const char* ComparisonName(Comparison op);

// Whether `value op bound` holds.
bool Holds(Comparison op, double value, double bound);

// An assertion on paths over a time window, e.g. "xpos[torso][2] > 0.8 during [0, 2]"
// or "maxabs(qvel[*]) < 50", "mean(qvel[0]) > 0.3 during [7, 11]".
struct Assertion {
  std::string text;
  Reduction reduce = Reduction::kEach;
  std::vector<Path> paths;  // every path must satisfy it ('*' expanded)
  Comparison op = Comparison::kLess;
  double bound = 0;
  double from = 0, to = -1;  // window in s; to < 0 means the end of the run
};

// A user's behaviour scenario.
struct Scenario {
  std::string file;
  std::string name;
  double duration = 2;              // s
  int keyframe = -1;                // keyframe to start from, -1: the audit's reference pose
  std::vector<Assignment> initial;  // state / parameter assignments after the keyframe
  std::vector<ControlSchedule> controls;
  std::vector<Assertion> assertions;
};

// Parses one assertion. @throws ValueError / PathError quoting it.
Assertion ParseAssertion(const Model& model, const std::string& text);

// Reads a scenario from a .json or .toml file. @throws ValueError naming the file and
// the entry at fault (file:line:column for TOML, a JSON pointer for JSON), IoError when it
// cannot be read.
Scenario LoadScenario(const Model& model, const std::string& file);

}  // namespace plumb

#endif  // PLUMB_INCLUDE_PLUMB_SCENARIO_H_
