// The scenario language: control schedules, assertions and their parts. Reading a
// scenario file is scenario_file.cc; judging assertions over a run is assertion_tally.cc.

#include "plumb/scenario.h"

#include <cmath>
#include <cstring>
#include <optional>
#include <string_view>

#include "core/strings.h"
#include "plumb/error.h"
#include "scenario/assertion_form.h"

namespace plumb {
using internal::ParseNumber;
using internal::Split;
using internal::Trim;

// The names, in the order of each enum's values.
const char* ControlShapeName(ControlShape shape) {
  static constexpr const char* kNames[] = {"constant", "step", "ramp", "sine"};
  return kNames[static_cast<int>(shape)];
}

const char* ReductionName(Reduction reduce) {
  static constexpr const char* kNames[] = {"", "maxabs", "max", "min", "final", "mean"};
  return kNames[static_cast<int>(reduce)];
}

const char* ComparisonName(Comparison op) {
  static constexpr const char* kNames[] = {"<", "<=", ">", ">="};
  return kNames[static_cast<int>(op)];
}

bool Holds(Comparison op, double value, double bound) {
  switch (op) {
    case Comparison::kLess:
      return value < bound;
    case Comparison::kLessEqual:
      return value <= bound;
    case Comparison::kGreater:
      return value > bound;
    case Comparison::kGreaterEqual:
      return value >= bound;
  }
  return false;
}

double ControlSchedule::At(double t) const {
  switch (type) {
    case ControlShape::kConstant:
      return value;
    case ControlShape::kStep:
      return t < at ? before : value;
    case ControlShape::kRamp:
      if (t <= start) return before;
      if (t >= end) return to;
      return before + (to - before) * (t - start) / (end - start);
    case ControlShape::kSine:
      break;
  }
  return value + amplitude * std::sin(2 * M_PI * frequency * t + phase);
}

namespace internal {

Assertion ParseAssertionForm(const std::string& text, const AssertionResolver& resolve) {
  Assertion a;
  a.text = text;
  auto bad = [&](const std::string& why) {
    return ValueError("assertion '" + text + "': " + why +
                      ". Write e.g. 'xpos[torso][2] > 0.8 during [0, 2]' or "
                      "'maxabs(qvel[*]) < 50'.");
  };
  std::string_view s = Trim(text);
  // split off "during [a, b]"
  std::size_t during = s.find("during");
  std::string_view window;
  if (during != std::string_view::npos) {
    window = Trim(s.substr(during + 6));
    s = Trim(s.substr(0, during));
    if (window.size() < 5 || window.front() != '[' || window.back() != ']') {
      throw bad("the window must look like [0, 2]");
    }
    std::vector<std::string> ends = Split(window.substr(1, window.size() - 2), ',');
    std::optional<double> from = ends.size() == 2 ? ParseNumber(ends[0]) : std::nullopt;
    std::optional<double> to = ends.size() == 2 ? ParseNumber(ends[1]) : std::nullopt;
    if (!from || !to || !(*from <= *to) || *from < 0)
      throw bad("the window must be [a, b], 0 <= a <= b");
    a.from = *from;
    a.to = *to;
  }
  // the comparison
  std::size_t op_at = std::string_view::npos;
  for (Comparison op : {Comparison::kLessEqual, Comparison::kGreaterEqual, Comparison::kLess,
                        Comparison::kGreater}) {
    std::size_t at = s.find(ComparisonName(op));
    if (at != std::string_view::npos && (op_at == std::string_view::npos || at < op_at)) {
      op_at = at;
      a.op = op;
    }
    if (op_at != std::string_view::npos && std::strlen(ComparisonName(op)) == 2 && at == op_at) {
      break;
    }
  }
  if (op_at == std::string_view::npos) throw bad("no comparison (<, <=, >, >=)");
  std::optional<double> bound = ParseNumber(s.substr(op_at + std::strlen(ComparisonName(a.op))));
  if (!bound || !std::isfinite(*bound)) throw bad("the right-hand side must be a number");
  a.bound = *bound;
  std::string_view lhs = Trim(s.substr(0, op_at));
  // NAME( ... ): a name is a whole word before its parenthesis, so "max" never takes
  // "maxabs(...)" (nor a path that starts with a reduction's name)
  for (Reduction reduce : {Reduction::kMaxAbs, Reduction::kMax, Reduction::kMin, Reduction::kFinal,
                           Reduction::kMean}) {
    std::string_view name(ReductionName(reduce));
    if (lhs.substr(0, name.size()) != name || lhs.size() <= name.size() + 1) continue;
    std::string_view inner = Trim(lhs.substr(name.size()));
    if (inner.front() == '(' && inner.back() == ')') {
      a.reduce = reduce;
      lhs = Trim(inner.substr(1, inner.size() - 2));
      break;
    }
  }
  if (lhs.empty()) throw bad("nothing to compare before the comparison");
  resolve(lhs, &a);
  return a;
}

void ResolvePaths(const Model& model, std::string_view lhs, Assertion* a) {
  for (const Path& p : ExpandPath(model, lhs)) {
    for (Path& one : ScalarPaths(p)) a->paths.push_back(std::move(one));
  }
}

}  // namespace internal

Assertion ParseAssertion(const Model& model, const std::string& text) {
  return internal::ParseAssertionForm(
      text, [&](std::string_view lhs, Assertion* a) { internal::ResolvePaths(model, lhs, a); });
}

}  // namespace plumb
