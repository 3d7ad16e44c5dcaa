#include "scenario/assertion_tally.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <utility>

namespace plumb::internal {

AssertionTally::AssertionTally(const std::vector<Assertion>& assertions)
    : AssertionTally(assertions, {}) {}

AssertionTally::AssertionTally(const std::vector<Assertion>& assertions,
                               std::vector<std::vector<std::string>> names)
    : assertions_(assertions),
      names_(std::move(names)),
      tallies_(assertions.size()),
      paths_(assertions.size(), false) {
  names_.resize(assertions.size());
  for (std::size_t a = 0; a < assertions.size(); ++a) {
    if (names_[a].empty()) {
      paths_[a] = true;
      for (const Path& p : assertions[a].paths) names_[a].push_back(p.text);
    }
    tallies_[a].resize(names_[a].size());
  }
}

void AssertionTally::Add(const Assertion& as, double v, double time, Tally* t) {
  bool first = t->count == 0;
  switch (as.reduce) {
    case Reduction::kEach:
      if (t->ok && !Holds(as.op, v, as.bound)) {
        t->ok = false;
        t->first_bad = v;
        t->first_bad_time = time;
      }
      break;
    case Reduction::kMaxAbs:
      t->reduced = first ? std::fabs(v) : std::max(t->reduced, std::fabs(v));
      break;
    case Reduction::kMax:
      t->reduced = first ? v : std::max(t->reduced, v);
      break;
    case Reduction::kMin:
      t->reduced = first ? v : std::min(t->reduced, v);
      break;
    case Reduction::kFinal:
      t->reduced = v;  // the last sample in the window
      break;
    case Reduction::kMean:
      t->sum += v;
      t->reduced = t->sum / static_cast<double>(t->count + 1);
      break;
  }
  ++t->count;
}

bool AssertionTally::InWindow(std::size_t a, double time) const {
  const Assertion& as = assertions_[a];
  double end = as.to < 0 ? INFINITY : as.to;
  return time >= as.from - 1e-12 && time <= end + 1e-12;
}

void AssertionTally::SampleValue(std::size_t a, std::size_t k, double value, double time) {
  if (InWindow(a, time)) Add(assertions_[a], value, time, &tallies_[a][k]);
}

void AssertionTally::Sample(const Model& model, const Data& data, double time) {
  for (std::size_t a = 0; a < assertions_.size(); ++a) {
    if (!paths_[a] || !InWindow(a, time)) continue;
    const Assertion& as = assertions_[a];
    for (std::size_t k = 0; k < as.paths.size(); ++k) {
      SampleValue(a, k, ReadValue(model, data, as.paths[k]), time);
    }
  }
}

AssertionTally::Verdict AssertionTally::Judge(std::size_t a) const {
  const Assertion& as = assertions_[a];
  const std::vector<std::string>& names = names_[a];
  const std::vector<Tally>& tallies = tallies_[a];
  const char* noun = paths_[a] ? "paths" : "signals";
  Verdict verdict{true, "no sample in the window"};
  bool none = std::all_of(tallies.begin(), tallies.end(), [](const Tally& t) { return !t.count; });
  if (none) return {false, "no sample in the window"};
  double closest = INFINITY;
  for (std::size_t k = 0; k < names.size(); ++k) {
    const Tally& t = tallies[k];
    const std::string& name = names[k];
    if (!t.count) return {false, fmt::format("no sample of {} in the window", name)};
    if (as.reduce == Reduction::kEach) {
      if (!t.ok) {
        return {false,
                fmt::format("{} = {:.6g} at t = {:g} s", name, t.first_bad, t.first_bad_time),
                t.first_bad};
      }
      verdict.measured = names.size() == 1
                             ? "holds at every step"
                             : fmt::format("holds at every step for all {} {}", names.size(), noun);
      continue;
    }
    std::string value = fmt::format("{}({}) = {:.6g}", ReductionName(as.reduce), name, t.reduced);
    if (!Holds(as.op, t.reduced, as.bound)) return {false, value, t.reduced};
    double margin = std::fabs(t.reduced - as.bound);
    if (margin < closest) {
      closest = margin;
      verdict.value = t.reduced;
      verdict.measured =
          value + (names.size() > 1 ? fmt::format(" (closest of {} {})", names.size(), noun) : "");
    }
  }
  return verdict;
}

}  // namespace plumb::internal
