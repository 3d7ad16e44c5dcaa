// Parameter sweeps: the Cartesian product of varied values, each case an independent
// run from the same nominal model, measured with one or more metrics, in parallel.
//
// Example:
//   plumb::SweepSpec spec;
//   spec.axes = {plumb::ParseSweepAxis(model, "dof_damping[hinge]=0,0.05,1")};
//   spec.metrics = {plumb::ParseMetric(model, "qpos[hinge]@2")};
//   spec.sets = {plumb::ParseAssignment(model, "qpos[hinge]=0.7")};
//   std::vector<plumb::SweepCase> cases = plumb::Sweep(model, spec);   // in case order
//
// Thread-safety: Sweep runs on spec.threads threads of a TBB arena, each on its own copy of
// `model`, which is only read: sweeps may run at once from several threads, also on one Model.
// `emit` is called on the calling thread, spec.progress on the workers. The calling thread may
// run cases too: its pending MuJoCo warnings are dropped (TakeMujocoWarnings). The other
// functions keep no state and only read their arguments.

#ifndef PLUMB_INCLUDE_PLUMB_SWEEP_H_
#define PLUMB_INCLUDE_PLUMB_SWEEP_H_

#include <functional>
#include <string>
#include <string_view>
#include <vector>

#include "plumb/metric.h"

namespace plumb {

// One varied path and its values. A list (`V1,V2,...`) is held value by value; a range
// (`START:STOP:COUNT`) is made on demand, so `=0:1:100000000` costs no memory.
struct SweepAxis {
  std::string text;  // as typed
  Path path;         // a single element

  std::size_t size() const;
  // The i-th value as an assignment of `path`, and as the table shows it ("RK4", "0.05").
  Assignment Value(std::size_t i) const;
  std::string Label(std::size_t i) const;

  // a list: one assignment and label per value
  std::vector<Assignment> listed;
  std::vector<std::string> listed_labels;
  // a range: `count` evenly spaced values from `start` to `stop`, both ends as written
  double start = 0, stop = 0;
  long count = 0;
  Assignment prototype;  // path and warnings of the range; values[0] is replaced
};

// Parses `PATH=V1,V2,...` (numbers or enumeration names) or `PATH=START:STOP:COUNT`
// (COUNT evenly spaced values, both ends included).
// @throws ValueError naming the option, also for an unknown path (never PathError).
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
  int runs = 0;  // simulations run: one per run length its metrics need (0 when refused)
};

// A simulation each case runs: `until` s long, measuring the metrics `metrics` (indices into
// SweepSpec::metrics).
struct SweepRun {
  double until = 0;
  std::vector<std::size_t> metrics;
};

// The runs of one case: one per run length its metrics need (a value@T's or state@T's T, else
// `spec.until`, else the metric's default), in the order first met; metrics of one length
// share a run (9 cases x 2 metrics of one length are 9 simulations).
std::vector<SweepRun> SweepRuns(const SweepSpec& spec);

// Number of cases: the product of the axes' sizes.
// @throws ValueError when the product passes 2^53 (no sweep can run that many).
long CaseCount(const std::vector<SweepAxis>& axes);

// Refuses two axes that write the same element (`dof_damping[hinge]` and
// `dof_damping[0]`): the later one would silently win. @throws ValueError naming both.
void RequireDistinctAxes(const std::vector<SweepAxis>& axes);

// Which value of each axis case `index` takes (first axis slowest, last fastest).
std::vector<std::size_t> CaseChoice(const std::vector<SweepAxis>& axes, long index);

// Checks a spec before anything runs: at least one metric, threads >= 1, distinct axes, and
// every metric time a whole number of steps of every timestep a case uses.
// @throws ValueError.
void ValidateSweepSpec(const Model& model, const SweepSpec& spec);

// Runs the cases 0 .. CaseCount-1 that are not in `skip` (sorted; for --resume) and calls
// `emit` once per case in increasing index order, from the calling thread, as soon as it and
// every case before it are done: memory does not grow with the number of cases. When `stop`
// asks (the running cases see it at their next step, those not started are skipped), every
// case that finished is emitted (those after the first unfinished one last, in increasing
// index order with gaps) and Interrupted is thrown. A range value that
// fails CheckAssignable (see ParseSweepAxis) is that case's problem. Bit-identical for any
// thread count. @throws ValueError as ValidateSweepSpec; Interrupted; MujocoError; what `emit`
// throws.
void Sweep(const Model& model, const SweepSpec& spec, const std::vector<long>& skip,
           const std::function<void(const SweepCase&)>& emit,
           const StopToken& stop = {});

// Runs every case and returns them all (a small sweep; the streaming Sweep above for large
// ones). Results come back in case order and are bit-identical whatever the
// thread count: each case starts from a fresh copy of the nominal model in its worker's
// own buffer. A diverged case is recorded (ok = false) and the sweep goes on.
// @throws ValueError as ValidateSweepSpec does; MujocoError from MuJoCo.
std::vector<SweepCase> Sweep(const Model& model, const SweepSpec& spec);

}  // namespace plumb

#endif  // PLUMB_INCLUDE_PLUMB_SWEEP_H_
