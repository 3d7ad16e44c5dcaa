// ParseRehearsalAssertion (plumb/rehearse.h): the scenario language's form
// (scenario/assertion_form.h), its left-hand side a path of the model or a motor signal.

#include <fmt/format.h>

#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "core/mujoco_compat.h"
#include "core/strings.h"
#include "plumb/error.h"
#include "plumb/rehearse.h"
#include "scenario/assertion_form.h"

namespace plumb {
namespace {
using internal::Echo;
using internal::Join;
using internal::ParseIndex;
using internal::Trim;
using Signal = RehearsalAssertion::Signal;

struct SignalName {
  const char* name;
  Signal signal;
};
constexpr SignalName kSignals[] = {{"tracking_error", Signal::kTrackingError},
                                   {"torque", Signal::kTorque},
                                   {"saturated", Signal::kSaturated}};

// The bridge's motors as MotorMap::Bind names them (src/bridge/motor_map.cc), in slot order:
// the configured actuators or joints ("" for an empty slot), else every actuator in order; an
// unnamed actuator reads as its number.
std::vector<std::string> MotorNames(const Model& model, const BridgeConfig& config) {
  if (!config.motors.empty()) return config.motors;
  std::vector<std::string> names;
  for (int u = 0; u < compat::ActuatorCount(model.get()); ++u) {
    std::string name = model.Name(mjOBJ_ACTUATOR, u);
    names.push_back(name.empty() ? std::to_string(u) : name);
  }
  return names;
}

// The motors `which` names: a motor's name, its number (its slot), or '*' (every motor, empty
// slots left out).
std::vector<int> Motors(const std::vector<std::string>& names, std::string_view which,
                        const std::string& text) {
  std::vector<int> motors;
  std::vector<std::string> named;  // the motors, for the message
  for (std::size_t i = 0; i < names.size(); ++i) {
    if (names[i].empty()) continue;
    motors.push_back(static_cast<int>(i));
    named.push_back(names[i]);
  }
  if (which == "*") return motors;
  for (int i : motors) {
    if (names[i] == which) return {i};
  }
  std::optional<long> number = ParseIndex(which);
  if (number && *number < static_cast<long>(names.size())) {
    if (!names[*number].empty()) return {static_cast<int>(*number)};
    throw ValueError(fmt::format(
        "assertion '{}': slot {} is empty in the bridge's motors = [...]: the model has no motor "
        "there; name one of its motors ({}) or '*' for each.",
        Echo(text), *number, Join(named, ", ")));
  }
  throw ValueError(fmt::format(
      "assertion '{}': '{}' is not a motor of the bridge: name one of its {} motors ({}), a motor "
      "number 0..{} (its slot), or '*' for each.",
      Echo(text), Echo(which), named.size(), Join(named, ", "),
      static_cast<long>(names.size()) - 1));
}

}  // namespace

RehearsalAssertion ParseRehearsalAssertion(const Model& model, const BridgeConfig& config,
                                           const std::string& text) {
  RehearsalAssertion r;
  r.assertion = internal::ParseAssertionForm(text, [&](std::string_view lhs, Assertion* a) {
    for (const SignalName& s : kSignals) {
      std::string_view name(s.name);
      if (lhs.substr(0, name.size()) != name) continue;
      std::string_view rest = Trim(lhs.substr(name.size()));
      if (rest.empty() || rest.front() != '[') continue;  // a path such as torque_x[...]
      if (rest.back() != ']' || rest.find(']') != rest.size() - 1) {
        throw ValueError(fmt::format(
            "assertion '{}': {} takes one motor in brackets: {}[FR_hip_joint], {}[0] or {}[*].",
            Echo(text), name, name, name, name));
      }
      std::vector<std::string> names = MotorNames(model, config);
      r.signal = s.signal;
      r.motors = Motors(names, Trim(rest.substr(1, rest.size() - 2)), text);
      for (int m : r.motors) r.names.push_back(fmt::format("{}[{}]", name, names[m]));
      return;
    }
    internal::ResolvePaths(model, lhs, a);
  });
  return r;
}

}  // namespace plumb
