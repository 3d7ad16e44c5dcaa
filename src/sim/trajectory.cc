#include "plumb/trajectory.h"

#include <algorithm>

#include "core/demand.h"
#include "plumb/timing.h"

namespace plumb {

std::vector<std::string> SplitPathList(const std::string& text) {
  std::vector<std::string> parts;
  std::string current;
  int depth = 0;
  for (char c : text) {
    if (c == '[') ++depth;
    if (c == ']') --depth;
    if (c == ',' && depth == 0) {
      parts.push_back(current);
      current.clear();
    } else {
      current += c;
    }
  }
  parts.push_back(current);
  return parts;
}

std::vector<Path> RunColumns(const Model& model, const std::vector<std::string>& texts) {
  if (texts.empty()) return DefaultColumns(model);
  std::vector<Path> columns;
  for (const std::string& list : texts) {
    for (const std::string& text : SplitPathList(list)) {
      for (const Path& p : ExpandPath(model, text)) {
        for (Path& one : ScalarPaths(p)) columns.push_back(std::move(one));
      }
    }
  }
  return columns;
}

double RunEvery(std::optional<double> every, double timestep) {
  constexpr double kWanted = 0.1;
  if (every) return *every;
  // 0.1 s itself when it falls on steps, so the sample times print as the chapter's
  return WholeSteps(kWanted, timestep) ? kWanted : DefaultEvery(timestep, kWanted);
}

long SampleCount(const Schedule& schedule) { return schedule.steps / schedule.stride + 1; }

TrajectorySink::TrajectorySink(long rows) : capacity_(std::max(0L, rows)) {}

void TrajectorySink::Begin(const std::vector<Path>& columns) {
  names_.clear();
  for (const Path& p : columns) names_.push_back(p.text);
  rows_ = 0;
  // one allocation, exactly the planned size: the samples are written in place
  values_.clear();
  values_.shrink_to_fit();
  values_.reserve(static_cast<std::size_t>(capacity_) * columns.size());
}

void TrajectorySink::Sample(const std::vector<double>& row) {
  PLUMB_DEMAND(rows_ < capacity_ && row.size() == names_.size());
  values_.insert(values_.end(), row.begin(), row.end());
  ++rows_;
}

std::vector<double> TrajectorySink::Take() {
  std::vector<double> out = std::move(values_);
  values_ = {};
  return out;
}

}  // namespace plumb
