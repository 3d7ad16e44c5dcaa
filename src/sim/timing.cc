#include "plumb/timing.h"

#include <fmt/format.h>
#include <unistd.h>

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

namespace {

// Why `time` s cannot be run at `timestep` s: more than kMostSteps steps. `from` says where
// the timestep comes from ("the model's timestep; "), or is empty.
std::string TooManySteps(double time, double timestep, const std::string& from) {
  return fmt::format(
      "{:g} s is {:.3g} steps of {:g} s ({}plumb counts steps exactly up to 2^53, 9.0e15); "
      "give a shorter time.",
      time, time / timestep, timestep, from);
}

}  // namespace

std::optional<long> WholeSteps(double time, double timestep) {
  if (!std::isfinite(time) || !std::isfinite(timestep) || !(timestep > 0)) return std::nullopt;
  double ratio = time / timestep;
  double nearest = std::round(ratio);
  if (!(std::fabs(ratio - nearest) <= 1e-9 * std::max(1.0, nearest))) return std::nullopt;
  if (!(nearest < kMostSteps)) return std::nullopt;  // steps stay exact
  return static_cast<long>(nearest);
}

long RequireWholeSteps(double time, double timestep, const std::string& argument,
                       const std::string& value, const std::string& source, long min_steps) {
  std::optional<long> steps = WholeSteps(time, timestep);
  if (steps && *steps >= min_steps) return *steps;
  std::string from = source.empty() ? "" : source + "; ";
  double ratio = time / timestep;
  // no nearest whole time to suggest when the time itself is out of reach
  if (!std::isfinite(time)) {
    throw ArgumentError(argument, value, "the time must be a finite number of seconds.");
  }
  if (!(std::fabs(ratio) < kMostSteps)) {
    throw ArgumentError(argument, value, TooManySteps(time, timestep, from));
  }
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

long RequireStepsToReach(double until, double timestep, const std::string& argument,
                         const std::string& value, const std::string& source) {
  if (!(timestep > 0) || !std::isfinite(timestep)) {
    throw ValueError(fmt::format(
        "the timestep is {:g} s; it must be a positive number (set opt.timestep).", timestep));
  }
  std::string shown = value.empty() ? fmt::format("{:g}", until) : value;
  if (!(until >= 0) || !std::isfinite(until)) {
    throw ArgumentError(argument, shown, "the time must be a finite number of seconds >= 0.");
  }
  if (!(until / timestep < kMostSteps)) {
    throw ArgumentError(argument, shown,
                        TooManySteps(until, timestep, source.empty() ? "" : source + "; "));
  }
  return StepsToReach(until, timestep);
}

void RequireMemoryFor(double bytes, const std::string& what, const std::string& argument,
                      const std::string& value) {
  long pages = sysconf(_SC_PHYS_PAGES), page = sysconf(_SC_PAGESIZE);
  double memory = pages > 0 && page > 0 ? static_cast<double>(pages) * page : 0;
  if (std::isfinite(bytes) && (memory == 0 || bytes <= memory)) return;
  throw ArgumentError(argument, value,
                      fmt::format("{} take {:.3g} bytes, more than this machine's memory ({:.3g} "
                                  "bytes); ask for less.",
                                  what, bytes, memory));
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
