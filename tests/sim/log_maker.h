// Logs made by plumb itself from known parameters, for the replay and identification tests:
// a model driven through input paths by known signals (optionally delayed on its way
// in), sampled every few steps, with Gaussian measurement noise.

#ifndef PLUMB_TESTS_SIM_LOG_MAKER_H_
#define PLUMB_TESTS_SIM_LOG_MAKER_H_

#include <fmt/format.h>

#include <cmath>
#include <functional>
#include <random>
#include <string>
#include <utility>
#include <vector>

#include "fixture.h"
#include "plumb/model.h"
#include "plumb/path.h"

namespace plumb::testing {

struct LogSpec {
  std::string model = kPendulum;
  std::vector<std::string> set;  // PATH=VALUE: the truth, and the start state
  std::string input = "qfrc_applied[hinge]";
  std::function<double(double)> u;  // the logged input at time t (none: no input column)
  std::vector<std::pair<std::string, std::function<double(double)>>> more_inputs;
  int delay_steps = 0;  // the inputs act this many steps after they are logged
  std::vector<std::string> measured = {"qpos[hinge]", "qvel[hinge]"};
  std::vector<double> noise;  // sigma per measured column (empty: none)
  double until = 3;
  int every = 1;  // steps between rows
  unsigned seed = 1;
};

// Simulates `spec` and writes its log to `path`; returns `path`.
inline std::string MakeLog(const std::string& path, const LogSpec& spec) {
  Model model = Model::Load(spec.model);
  Data data(model);
  std::vector<Assignment> set;
  for (const std::string& s : spec.set) set.push_back(ParseAssignment(model, s));
  ApplyAssignments(model, data, set);
  std::vector<Path> measured;
  for (const std::string& m : spec.measured) measured.push_back(ResolvePath(model, m));
  std::vector<std::pair<std::string, std::function<double(double)>>> inputs = spec.more_inputs;
  if (spec.u) inputs.insert(inputs.begin(), {spec.input, spec.u});
  std::vector<Path> input_paths;
  for (const auto& in : inputs) input_paths.push_back(ResolvePath(model, in.first));
  std::mt19937_64 random(spec.seed);
  std::normal_distribution<double> gauss;
  double dt = model->opt.timestep;
  long steps = std::lround(spec.until / dt);
  std::string csv = "time";
  for (const auto& in : inputs) csv += "," + in.first;
  for (const std::string& m : spec.measured) csv += "," + m;
  csv += "\n";
  for (long k = 0; k <= steps; ++k) {
    double t = k * dt;
    if (k % spec.every == 0) {
      csv += fmt::format("{}", t);
      for (const auto& in : inputs) csv += fmt::format(",{}", in.second(t));
      for (std::size_t i = 0; i < measured.size(); ++i) {
        double sigma = i < spec.noise.size() ? spec.noise[i] : 0;
        csv += fmt::format(",{}", ReadValue(model, data, measured[i]) + sigma * gauss(random));
      }
      csv += "\n";
    }
    if (k == steps) break;
    // the controller sets its inputs when it logs a row, and they act delay_steps later
    long held = std::max(0L, k - spec.delay_steps);
    double at = static_cast<double>(held - held % spec.every) * dt;
    for (std::size_t i = 0; i < inputs.size(); ++i) {
      WriteValues(model, data, input_paths[i], {inputs[i].second(at)});
    }
    mj_step(model.get(), data.get());
  }
  WriteFile(path, csv);
  return path;
}

// A chirp from 0.2 to 3 Hz over `seconds`, amplitude `a`: rich excitation.
inline std::function<double(double)> Chirp(double a, double seconds) {
  return [a, seconds](double t) {
    double f0 = 0.2, f1 = 3;
    return a * std::sin(2 * M_PI * (f0 * t + (f1 - f0) * t * t / (2 * seconds)));
  };
}

}  // namespace plumb::testing

#endif  // PLUMB_TESTS_SIM_LOG_MAKER_H_
