#include "plumb/timing.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "plumb/error.h"

namespace plumb {

double RunTimestep(const Model& model, const std::vector<Assignment>& sets) {
  double dt = model->opt.timestep;
  std::string source = "the model's opt.timestep";
  for (const Assignment& a : sets) {
    if (a.path.field == "opt.timestep" && !a.values.empty()) {
      dt = a.values[0];
      source = "set to " + Quoted(a.text);
    }
  }
  if (!(dt > 0) || !std::isfinite(dt)) {
    throw ValueError(
        fmt::format("the timestep is {:g} s ({}); it must be a positive number (set opt.timestep).",
                    dt, source));
  }
  return dt;
}

std::optional<long> WholeSteps(double time, double timestep) {
  if (!std::isfinite(time) || !std::isfinite(timestep) || !(timestep > 0)) return std::nullopt;
  double ratio = time / timestep;
  double nearest = std::round(ratio);
  if (!(std::fabs(ratio - nearest) <= 1e-9 * std::max(1.0, nearest))) return std::nullopt;
  if (!(nearest < 9007199254740992.0)) return std::nullopt;  // 2^53: steps stay exact
  return static_cast<long>(nearest);
}

long RequireWholeSteps(double time, double timestep, const std::string& argument,
                       const std::string& value, const std::string& source, long min_steps) {
  std::optional<long> steps = WholeSteps(time, timestep);
  if (steps && *steps >= min_steps) return *steps;
  std::string from = source.empty() ? "" : source + "; ";
  double ratio = time / timestep;
  double low = std::max(static_cast<double>(std::max(1L, min_steps)), std::floor(ratio));
  double high = std::max(low, std::ceil(ratio));
  std::string nearest = low == high
                            ? fmt::format("{:.10g}", low * timestep)
                            : fmt::format("{:.10g} or {:.10g}", low * timestep, high * timestep);
  if (steps) {
    throw ArgumentError(
        argument, value,
        fmt::format("{:g} s is {} step(s) of {:g} s ({}at least {} needed). Use {}.", time, *steps,
                    timestep, from, min_steps, nearest));
  }
  throw ArgumentError(
      argument, value,
      fmt::format("{:g} s is not a whole number of timesteps of {:g} s ({}it is {:.4g} steps); "
                  "times must fall on exact steps. Use {}, or change opt.timestep.",
                  time, timestep, from, ratio, nearest));
}

long StepsToReach(double until, double timestep) {
  std::optional<long> whole = WholeSteps(until, timestep);
  return whole ? *whole : static_cast<long>(std::ceil(until / timestep));
}

double DefaultEvery(double timestep, double wanted) {
  double steps = std::max(1.0, std::round(wanted / timestep));
  return steps * timestep;
}

}  // namespace plumb
