// Which bodies start asleep, and waking a model for testing (plumb/sleep.h).

#include "plumb/sleep.h"

#include <fmt/format.h>

#include "core/mujoco_compat.h"
#include "core/strings.h"

namespace plumb {
using internal::Join;

std::string SleepingStart::Describe() const {
  if (bodies.empty()) return "";
  std::vector<std::string> quoted;
  for (const std::string& b : bodies) quoted.push_back("'" + b + "'");
  bool one = bodies.size() == 1;
  return fmt::format("{} {} {} asleep (the sleep flag is on and {} sleep=\"init\")",
                     one ? "Body" : "Bodies", Join(quoted, ", "), one ? "starts" : "start",
                     one ? "its tree has" : "their trees have");
}

SleepingStart FindSleepingStart(const Model& model, const Data& data) {
  SleepingStart start;
  for (int body : compat::AsleepTreeRoots(model.get(), data.get())) {
    std::string name = model.Name(mjOBJ_BODY, body);
    start.bodies.push_back(name.empty() ? "body " + std::to_string(body) : name);
  }
  return start;
}

SleepingStart FindSleepingStart(Model& model, const ReferencePose& pose,
                                const std::vector<Assignment>& sets) {
  ReferencePose own = pose;
  own.into_range.clear();
  Data data(model);
  StartAtPose(model, data, own, sets);
  data.Forward();
  return FindSleepingStart(model, data);
}

void WakeForTesting(Model& model) { compat::DisableSleep(model.get_mutable()); }

}  // namespace plumb
