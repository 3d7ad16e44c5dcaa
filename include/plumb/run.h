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
//
// Thread-safety: Run may be called from several threads at once with distinct Data objects; a
// Model is only read. The sink and the callbacks are called on the calling thread; a
// DerivedRefresher serves one thread at a time. MuJoCo warnings are counted from the Data into
// RunResult and also reach the calling thread's buffer (TakeMujocoWarnings), which Run does not
// clear.

#ifndef PLUMB_INCLUDE_PLUMB_RUN_H_
#define PLUMB_INCLUDE_PLUMB_RUN_H_

#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "plumb/model.h"
#include "plumb/path.h"
#include "plumb/stop.h"

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
  // The time column: false, the sample's nominal time (start + step * timestep, rounded to
  // their decimals: 0.1); true, the data's clock as MuJoCo accumulates it (mjData.time:
  // 0.10000000000000007), what a Python user compares with their own MjData.
  bool clock_time = false;
  // When its source asks to stop (e.g. from a signal handler), Run throws Interrupted before
  // the next step. Default: never.
  StopToken stop;
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
  long step = 0;  // by the data's clock: the state after step n is at t = n * timestep
  double time = 0;  // simulation time of this state, s
  std::vector<double> qpos, qvel, act, ctrl;
  // Everything the next step starts from, as one vector: on MuJoCo 3.5+ mj_getState's
  // mjSTATE_INTEGRATION (also the warm start, applied forces, mocap, eq_active, userdata,
  // plugin state, and the history of delays and 4.0's plastic state), for mj_setState; on
  // 2.x time, qpos, qvel, act, qacc_warmstart, ctrl, qfrc_applied, xfrc_applied, mocap_pos
  // and mocap_quat. IntegrationStateLayout() names what it holds.
  std::vector<double> integration;
  // Accelerations (length nv) MuJoCo computes at this state; filled only for the bad
  // state of a divergence that MuJoCo's own checks caught (they reset the data, so plumb
  // recomputes them from the saved state).
  std::vector<double> qacc;
  std::string note;  // what this state is, when it needs saying (empty otherwise)
};

// Copies the state `data` holds, labelled as the state after `step` steps.
StateSnapshot Snapshot(const Model& model, const Data& data, long step);

// What to tell a user whose run MuJoCo stopped with fatal error `what` (a MujocoError's
// text): the error, and for an arena overflow (mj_stackAlloc, "out of memory") the arena's
// size now and what to raise. One sentence, for a check row that stands in for the run.
std::string FatalRunProblem(const Model& model, const std::string& what);

// Puts `state` back into `data` (all of StateSnapshot::integration), then calls mj_forward.
void Restore(const Model& model, Data& data, const StateSnapshot& state);

// What StateSnapshot::integration holds with the MuJoCo plumb was built with:
// "mjSTATE_INTEGRATION", or the list of 2.x's parts.
const char* IntegrationStateLayout();

// One kind of MuJoCo warning raised during a run.
struct WarningSummary {
  std::string kind;       // "INERTIA", "CONTACTFULL", "BADQACC", ...
  int count = 0;          // how many times MuJoCo raised it
  long first_step = 0;    // the step during which it was first raised (step n ends at n * dt)
  double first_time = 0;  // simulation time at the start of that step, s (MuJoCo's "Time =")
  std::string message;    // MuJoCo's text for the last occurrence
};

// Why and where a run stopped early.
struct Divergence {
  std::string reason;  // one sentence: what went bad, where, what MuJoCo did
  // The state the failing step started from (it passed every check), with the ctrl
  // that step applied: set it, call mj_forward, then mj_step once to reproduce.
  StateSnapshot last_good;
  // The bad state: right after the failing step when plumb's checks caught it; when
  // MuJoCo's mj_checkPos/Vel/Acc caught it (they reset the data to qpos0 in the middle
  // of the step), the state they found bad, with its recomputed qacc.
  StateSnapshot bad;
  bool reset_by_mujoco = false;  // MuJoCo's own check fired and reset the data
  std::string element;           // the bad element, e.g. "qacc[0] (joint 'slider')"
};

struct RunResult {
  bool diverged = false;
  long steps = 0;    // steps taken
  long samples = 0;  // rows given to the sink
  std::vector<WarningSummary> warnings;
  std::optional<Divergence> divergence;
};

// Steps `data` from its current state for the schedule of `spec`, giving the sink a row
// at every sample (the first at the current state). When a column is a derived quantity
// (xpos, sensordata, energy, ...), mj_forward runs before each sample so the row holds
// values of the sampled state (after mj_step they still describe the state before the
// step); this re-evaluation changes neither the trajectory nor the warning counts.
// Sample times are start + k*timestep, not the accumulated d->time. After every step,
// checks qpos, qvel, act and qacc for NaN/Inf or magnitudes above MuJoCo's limit (1e10)
// and whether MuJoCo's own checks reset the state; on the first failure it stops and
// returns with `diverged` set. @throws ValueError (see MakeSchedule), Interrupted, MujocoError, and
// whatever the sink throws; PathError (see ReadValue) when a sampled constraint or contact
// element lies beyond the rows the data holds at that step.
RunResult Run(const Model& model, Data& data, const RunSpec& spec, SampleSink& sink);

// Recomputes the derived quantities (xpos, sensordata, energy, contacts, qacc, and what
// MuJoCo computes only on request: energy without its flag, cacc, cfrc_int, cfrc_ext) of
// the state `data` holds, as mj_forward does, without changing the trajectory that follows
// or counting MuJoCo warnings again. After mj_step they still describe the state before
// the step (with RK4, an intermediate stage): call this before reading them in an
// after_step callback. Costs about one mj_forward. Holds scratch buffers sized for one
// model, so calling it every step does not allocate. operator() @throws MujocoError.
class DerivedRefresher {
 public:
  explicit DerivedRefresher(const Model& model);
  void operator()(Data& data);

 private:
  const mjModel* m_;
  std::vector<mjtNum> qpos_, warmstart_;
};

// One-off form of DerivedRefresher. @throws MujocoError.
void RefreshDerived(const Model& model, Data& data);

}  // namespace plumb

#endif  // PLUMB_INCLUDE_PLUMB_RUN_H_
