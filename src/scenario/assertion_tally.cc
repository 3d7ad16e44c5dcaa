#include "scenario/assertion_tally.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

namespace plumb::internal {

AssertionTally::AssertionTally(const std::vector<Assertion>& assertions)
    : assertions_(assertions), tallies_(assertions.size()) {
  for (std::size_t a = 0; a < assertions.size(); ++a) {
    tallies_[a].resize(assertions[a].paths.size());
  }
}

void AssertionTally::Add(Reduction reduce, Comparison op, double bound, double v, double time,
                         Tally* t) {
  switch (reduce) {
    case Reduction::kEach:
      if (t->ok && !Holds(op, v, bound)) {
        t->ok = false;
        t->first_bad = v;
        t->first_bad_time = time;
      }
      break;
    case Reduction::kMaxAbs:
      t->reduced = t->seen ? std::max(t->reduced, std::fabs(v)) : std::fabs(v);
      break;
    case Reduction::kMax:
      t->reduced = t->seen ? std::max(t->reduced, v) : v;
      break;
    case Reduction::kMin:
      t->reduced = t->seen ? std::min(t->reduced, v) : v;
      break;
    case Reduction::kFinal:
      t->reduced = v;  // the last sample in the window
      break;
  }
  t->seen = true;
}

void AssertionTally::Sample(const Model& model, const Data& data, double time) {
  for (std::size_t a = 0; a < assertions_.size(); ++a) {
    const Assertion& as = assertions_[a];
    double end = as.to < 0 ? INFINITY : as.to;
    if (time < as.from - 1e-12 || time > end + 1e-12) continue;
    for (std::size_t k = 0; k < as.paths.size(); ++k) {
      Add(as.reduce, as.op, as.bound, ReadValue(model, data, as.paths[k]), time, &tallies_[a][k]);
    }
  }
}

AssertionTally::Verdict AssertionTally::Judge(std::size_t a) const {
  const Assertion& as = assertions_[a];
  Verdict verdict{true, "no sample in the window"};
  double closest = INFINITY;
  for (std::size_t k = 0; k < as.paths.size(); ++k) {
    const Tally& t = tallies_[a][k];
    const std::string& name = as.paths[k].text;
    if (!t.seen) return {false, "no sample in the window"};
    if (as.reduce == Reduction::kEach) {
      if (!t.ok) {
        return {false,
                fmt::format("{} = {:.6g} at t = {:g} s", name, t.first_bad, t.first_bad_time)};
      }
      verdict.measured = as.paths.size() == 1
                             ? "holds at every step"
                             : fmt::format("holds at every step for all {} paths", as.paths.size());
      continue;
    }
    std::string value = fmt::format("{}({}) = {:.6g}", ReductionName(as.reduce), name, t.reduced);
    if (!Holds(as.op, t.reduced, as.bound)) return {false, value};
    double margin = std::fabs(t.reduced - as.bound);
    if (margin < closest) {
      closest = margin;
      verdict.measured =
          value +
          (as.paths.size() > 1 ? fmt::format(" (closest of {} paths)", as.paths.size()) : "");
    }
  }
  return verdict;
}

}  // namespace plumb::internal
