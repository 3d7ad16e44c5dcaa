// The check row every check writes (include/plumb/check.h).

#include "plumb/check.h"

#include <fmt/format.h>

#include <algorithm>

namespace plumb {

const char* CheckStatusName(CheckStatus status) {
  switch (status) {
    case CheckStatus::kPass:
      return "PASS";
    case CheckStatus::kWarn:
      return "WARN";
    case CheckStatus::kFail:
      return "FAIL";
    case CheckStatus::kSkip:
      return "SKIP";
  }
  return "?";
}

std::string ElementLabel(const CheckElement& element) {
  if (element.empty()) return "";
  if (element.name.empty()) return fmt::format("{} #{}", element.kind, element.id);
  if (element.id < 0) return fmt::format("{} '{}'", element.kind, element.name);  // an option
  return fmt::format("{} '{}' (id {})", element.kind, element.name, element.id);
}

std::string CheckRow::About() const { return element.empty() ? subject : ElementLabel(element); }

int CountStatus(const std::vector<CheckRow>& rows, CheckStatus status) {
  return static_cast<int>(std::count_if(rows.begin(), rows.end(),
                                        [&](const CheckRow& r) { return r.status == status; }));
}

int CountUnaccepted(const std::vector<CheckRow>& rows, CheckStatus status) {
  return static_cast<int>(std::count_if(rows.begin(), rows.end(), [&](const CheckRow& r) {
    return r.status == status && r.accepted.empty();
  }));
}

int CountAccepted(const std::vector<CheckRow>& rows) {
  return static_cast<int>(std::count_if(rows.begin(), rows.end(),
                                        [](const CheckRow& r) { return !r.accepted.empty(); }));
}

}  // namespace plumb
