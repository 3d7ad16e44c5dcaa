// What a run says besides its samples (run_notices.h).

#include "sim/run_notices.h"

#include <fmt/format.h>

#include <algorithm>

namespace plumb::internal {

void AddRunWarnings(const RunResult& result, const std::vector<std::string>& others,
                    Notices* notices) {
  if (notices == nullptr) return;
  for (const WarningSummary& w : result.warnings) {
    notices->Warn(NoticeTopic::kOther, "",
                  fmt::format("MuJoCo {} raised {} time(s), first in step {} (t = {:g} s): {}",
                              w.kind, w.count, w.first_step, w.first_time, w.message));
  }
  auto summarised = [&](const std::string& message) {
    return std::any_of(result.warnings.begin(), result.warnings.end(),
                       [&](const WarningSummary& w) {
                         return message.compare(0, w.message.size(), w.message) == 0;
                       });
  };
  for (const std::string& message : others) {
    if (!summarised(message)) notices->Warn(NoticeTopic::kOther, "", "MuJoCo: " + message);
  }
}

}  // namespace plumb::internal
