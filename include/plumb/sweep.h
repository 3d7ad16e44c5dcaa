// Parameter sweeps: the Cartesian product of varied values, each case an independent
// run from the same nominal model, measured with one or more metrics, in parallel.
//
// Example:
//   plumb::SweepSpec spec;
//   spec.axes = {plumb::ParseSweepAxis(model, "dof_damping[hinge]=0,0.05,1")};
//   spec.metrics = {plumb::ParseMetric(model, "qpos[hinge]@2")};
//   spec.sets = {plumb::ParseAssignment(model, "qpos[hinge]=0.7")};
//   std::vector<plumb::SweepCase> cases = plumb::Sweep(model, spec);   // in case order

#ifndef PLUMB_INCLUDE_PLUMB_SWEEP_H_
#define PLUMB_INCLUDE_PLUMB_SWEEP_H_

#include <functional>
#include <string>
#include <string_view>
#include <vector>

#include "plumb/metric.h"

namespace plumb {

// One varied path and its values.
struct SweepAxis {
  std::string text;                 // as typed
  Path path;                        // a single element
  std::vector<Assignment> values;   // one assignment per value, in order
  std::vector<std::string> labels;  // each value as typed ("RK4", "0.05")
};

// Parses `PATH=V1,V2,...` (numbers or enumeration names) or `PATH=START:STOP:COUNT`
// (COUNT evenly spaced values, both ends included).
// @throws PathError / ValueError naming the option.
SweepAxis ParseSweepAxis(const Model& model, std::string_view text);

struct SweepSpec {
  std::vector<Assignment> sets;  // applied to every case before the varied values
  std::vector<SweepAxis> axes;   // the first axis varies slowest
  std::vector<Metric> metrics;
  double until = 0;  // run length for period/maxabs/energy metrics; 0: each metric's default
  int threads = 1;   // worker threads (each owns one model copy and one data)
  // Called after each finished case with (done, total), from a worker thread; may be empty.
  std::function<void(long, long)> progress;
};

struct SweepCase {
  long index = 0;
  std::vector<std::size_t> choice;   // index into each axis's values
  std::vector<Measurement> metrics;  // one per metric; check ok / problem
};

// Number of cases: the product of the axes' sizes.
long CaseCount(const std::vector<SweepAxis>& axes);

// Runs every case. Results come back in case order and are bit-identical whatever the
// thread count: each case starts from a fresh copy of the nominal model in its worker's
// own buffer. A diverged case is recorded (ok = false) and the sweep goes on.
// @throws ValueError for no metric or threads < 1; MujocoError from MuJoCo.
std::vector<SweepCase> Sweep(const Model& model, const SweepSpec& spec);

}  // namespace plumb

#endif  // PLUMB_INCLUDE_PLUMB_SWEEP_H_
