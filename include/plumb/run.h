// Running a model: stepping with mj_step to a final time, sampling chosen paths at
// exact step indices, and watching every step for MuJoCo warnings and divergence.
//
// Example (the chapter's program):
//   plumb::Model model = plumb::Model::Load("models/pendulum.xml");
//   plumb::Data data(model);
//   plumb::ApplyAssignments(model, data, {plumb::ParseAssignment(model, "qpos[hinge]=0.7")});
//   plumb::RunSpec spec;                       // until 2 s, sample every 0.1 s
//   spec.columns = plumb::DefaultColumns(model);
//   MySink sink;                               // receives one row per sample
//   plumb::RunResult result = plumb::Run(model, data, spec, sink);

#ifndef PLUMB_INCLUDE_PLUMB_RUN_H_
#define PLUMB_INCLUDE_PLUMB_RUN_H_

#include <atomic>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "plumb/model.h"
#include "plumb/path.h"

namespace plumb {

// Receives the samples of a run as they are taken, so memory stays flat however long
// the run is.
class SampleSink {
 public:
  virtual ~SampleSink() = default;
  // Called once before the first sample with the column paths (each one element).
  virtual void Begin(const std::vector<Path>& columns) = 0;
  // One row, values in column order (the `time` column is the exact sample time).
  virtual void Sample(const std::vector<double>& row) = 0;
  // Called once after the last sample, also when the run diverged.
  virtual void End() {}
};

// A sink that discards everything (for benchmarks and runs kept for their result).
class NullSink : public SampleSink {
 public:
  void Begin(const std::vector<Path>&) override {}
  void Sample(const std::vector<double>&) override {}
};

// What to run.
struct RunSpec {
  double until = 2.0;         // final time in s (>= 0); steps = ceil(until / timestep)
  double every = 0.1;         // sampling interval in s; a whole multiple of the timestep
  std::vector<Path> columns;  // sampled paths, each a single element (see ScalarPaths)
  // When set and it becomes true (e.g. from a signal handler), Run throws Interrupted.
  const std::atomic<bool>* stop = nullptr;
  // Called before every mj_step with the step about to be taken (1-based), e.g. to
  // write ctrl; and after every step that passed the divergence checks, e.g. to
  // inspect contacts. Either may be empty.
  std::function<void(mjData*, long step)> before_step;
  std::function<void(const mjData*, long step)> after_step;
};

// The step counts a RunSpec implies for a model's timestep.
struct Schedule {
  long steps = 0;   // total mj_step calls
  long stride = 1;  // steps between samples; samples at steps 0, stride, 2*stride, ...
};

// Checks `until` and `every` against `timestep` (s) and returns the schedule.
// Sample times are k*stride*timestep, each computed in one multiplication, so they do
// not drift. @throws ValueError when until < 0 or not finite, or when every is not a
// positive whole multiple of the timestep (relative tolerance 1e-9).
Schedule MakeSchedule(double timestep, double until, double every);

// State of the simulation at one step, as a repro needs it.
struct StateSnapshot {
  long step = 0;
  double time = 0;  // d->time, s
  std::vector<double> qpos, qvel, act, ctrl;
};

// Copies the state of `data` at `step`.
StateSnapshot Snapshot(const mjModel* m, const mjData* d, long step);

// One kind of MuJoCo warning raised during a run.
struct WarningSummary {
  std::string kind;       // "INERTIA", "CONTACTFULL", "BADQACC", ...
  int count = 0;          // how many times MuJoCo raised it
  long first_step = 0;    // step after which it was first seen
  double first_time = 0;  // simulation time of that step, s
  std::string message;    // MuJoCo's text for the last occurrence
};

// Why and where a run stopped early.
struct Divergence {
  std::string reason;       // one sentence: what went bad, where, what MuJoCo did
  StateSnapshot last_good;  // the state after the last step that passed every check
  StateSnapshot bad;        // the state right after the step that failed
};

struct RunResult {
  bool diverged = false;
  long steps = 0;    // steps taken
  long samples = 0;  // rows given to the sink
  std::vector<WarningSummary> warnings;
  std::optional<Divergence> divergence;
};

// Steps `data` from its current state for the schedule of `spec`, giving the sink a row
// at every sample (the first at the current state). After every step, checks qpos,
// qvel, act and qacc for NaN/Inf or magnitudes above MuJoCo's limit (1e10) and whether
// MuJoCo's own checks reset the state; on the first failure it stops and returns with
// `diverged` set. @throws ValueError (see MakeSchedule), Interrupted, MujocoError, and
// whatever the sink throws.
RunResult Run(const Model& model, Data& data, const RunSpec& spec, SampleSink& sink);

// The chapter's common-error table, for the state a run is about to start from: one
// line of advice per problem found (empty when nothing looks wrong). Today: a system
// at rest in equilibrium with nothing driving it will not move.
std::vector<std::string> StartHints(const Model& model, const Data& data);

}  // namespace plumb

#endif  // PLUMB_INCLUDE_PLUMB_RUN_H_
