// Replaying a log in simulation: the logged inputs drive the model from the logged initial
// state, and what it measured is compared with what the simulation gives.
//
// - Inputs are held (zero-order hold) from each logged sample to the next; the simulation
//   steps at the model's timestep. Before an input's first sample its first value applies.
// - The start state is the logged qpos / qvel at the start (each element's first sample at
//   or after it); elements the log does not hold keep the model's qpos0 / zero velocity.
// - A measured sample at time t is compared with the simulation at t, linearly
//   interpolated between the two steps around it (exact when t falls on a step, as in a
//   log `plumb run` wrote).
// - window > 0: multiple shooting. The simulation restarts from the logged state at every
//   `window` seconds, so one early error does not spoil the rest.
// - input_delay: the inputs act this much later than logged (a link's latency);
//   sensor_delay: each measurement shows the state this much earlier than its time stamp.
//
// Example:
//   plumb::RobotLog log = plumb::LoadRobotLog(model, "decay.csv", model->opt.timestep);
//   plumb::ReplayResult r = plumb::Replay(model, log, {});
//   std::printf("%s: rms %g\n", r.signals[0].column.c_str(), r.signals[0].rms);
//
// Thread-safety: nothing keeps state and a Model is only read. Simulate writes only `data`, so
// it may run on several threads at once with distinct Data objects; Replay makes a Data of its
// own. MuJoCo warnings raised stay in the calling thread's buffer (TakeMujocoWarnings).

#ifndef PLUMB_INCLUDE_PLUMB_REPLAY_H_
#define PLUMB_INCLUDE_PLUMB_REPLAY_H_

#include <string>
#include <vector>

#include "plumb/model.h"
#include "plumb/robot_log.h"
#include "plumb/stop.h"

namespace plumb {

struct ReplayOptions {
  double window = 0;        // s; 0: one run from the start
  double input_delay = 0;   // s
  double sensor_delay = 0;  // s
  StopToken stop;           // when it asks, the replay ends with Interrupted (default: never)
};

// What the simulation gives for each measured signal of a log, at that signal's times.
struct Simulated {
  std::vector<std::vector<double>> values;  // [signal][sample], NaN after a divergence
  bool diverged = false;
  std::string problem;  // what went bad, when it did
};

// An rms error within this many times a signal's noise is that noise: what a model that
// explains all but the noise gives, with room for the noise estimate's own error (its median
// of third differences is some 10 % off on a few hundred samples).
constexpr double kFitNoiseMargin = 1.5;

struct SignalFit {
  std::string column;  // as the log names it
  std::string path;    // the plumb path
  long samples = 0;
  double rms = 0;         // root mean square of simulated - logged
  double max_abs = 0;     // largest |simulated - logged|
  double worst_time = 0;  // s, log time of the largest
  double fit = 0;         // %: 100 (1 - |e| / |y - mean y|); 100 is perfect, <= 0 no better
                          // than the logged mean
  double noise = 0;  // the log's noise (sigma) as its differences show it (NoiseFromDifferences)
  double noise_fit = 0;  // %: the fit of a model that explains all but that noise,
                         // 100 (1 - noise / rms(y - mean y))
  double spread = 0;     // rms(y - mean y), the signal's own spread
  // %: the fit judged against the noise, 100 (1 - sqrt(max(0, rms^2 - (m noise)^2)) / spread)
  // with m = kFitNoiseMargin: the error beyond what the log's noise explains. 100 for a model
  // that explains all but the noise, at any noise level, also on a nearly flat signal (whose
  // `fit` reads far below 0)
  double fit_beyond_noise = 0;
};

// The overall fit (%) of `signals` (CompareWithLog): all signals pooled, each sample's error
// beyond the noise and each signal's spread in units of that signal's noise, as identify
// weighs residuals: 100 (1 - sqrt(sum n max(0, rms^2 - (m noise)^2) / noise^2 /
// sum n spread^2 / noise^2)), m = kFitNoiseMargin. A nearly flat signal (its spread about its
// noise) weighs next to nothing in the denominator, so an exact model reads ~100 whatever it
// does to that signal's `fit`; an error many times its noise still counts in full. 100 for no
// signals.
double OverallFit(const std::vector<SignalFit>& signals);

struct ReplayResult {
  std::vector<SignalFit> signals;  // one per measured signal, in the log's order
  double fit = 0;                  // %: OverallFit of the signals
  Simulated simulated;
  std::vector<std::string> notes;  // start-state elements the log lacks, and the like
};

// Where each window starts (log time, s): the log's start, then (window > 0) the first time
// the logged state has a sample at or after each further `window` seconds.
// @throws ValueError when windows are asked for and the log lacks some of the state;
// ArgumentError (argument "window") for a window shorter than one timestep.
std::vector<double> WindowStarts(const Model& model, const RobotLog& log,
                                 const ReplayOptions& options);

// The window (an index into WindowStarts) whose simulation gives each sample of each measured
// signal: [signal][sample], in the log's order.
std::vector<std::vector<std::size_t>> SampleWindows(const Model& model, const RobotLog& log,
                                                    const ReplayOptions& options);

// The log's state columns (qpos and qvel elements), in the log's order: what each window
// starts from.
std::vector<const LogSignal*> StateSignals(const RobotLog& log);

// How many start-state offsets each window of `log` takes: one per StateSignals column, less
// one for each ball or free joint whose whole quaternion is logged (a quaternion has 3 degrees
// of freedom: its offsets are applied to the 3 components other than the one largest at the
// window's start, and the quaternion is normalized, so no offset is without effect).
std::size_t StartOffsetsPerWindow(const Model& model, const RobotLog& log);

// Simulates `log` on `model` with `data` as scratch (reset here). Deterministic.
// `start_offsets`, when given, is added to the logged start state: for each window in turn,
// StartOffsetsPerWindow values, one per StateSignals column in order but for each logged
// quaternion's largest component (identification fits the start state this way, since a
// logged start carries the measurement noise).
// @throws ValueError when a window needs the logged state and the log lacks some of it;
// Interrupted when options.stop asks; MujocoError.
Simulated Simulate(const Model& model, Data& data, const RobotLog& log,
                   const ReplayOptions& options,
                   const std::vector<double>* start_offsets = nullptr);

// Applies `sets` (assignment texts, ParseAssignment) to `model`, mj_setConst when an array
// changed. In a replay the state and the inputs come from the log, so only model parameters may
// be set. @throws PathError / ArgumentError as ParseAssignment does, and ArgumentError "set"
// for a state or input path.
void ApplyParameterAssignments(Model& model, const std::vector<std::string>& sets);

// Checks options a caller passes: @throws ArgumentError (argument "window", "input_delay" or
// "sensor_delay") for a window that is negative or not finite, or a delay that is not finite.
void CheckReplayOptions(const ReplayOptions& options);

// Simulates and compares. @throws as Simulate does.
ReplayResult Replay(const Model& model, const RobotLog& log, const ReplayOptions& options);

// A signal's measurement noise (sigma) from the log alone: the third differences of a smooth
// signal sampled finely are those of its noise, of variance 20 sigma^2 (1 + 9 + 9 + 1), and
// the median of their magnitude (0.6745 sigma for a normal noise) keeps the kinks a step in
// the inputs makes from counting. The signal's spread when it has fewer than 11 samples or no
// differences; 1 when it is constant. An overestimate where the samples are too coarse for
// the signal to look smooth.
double NoiseFromDifferences(const std::vector<double>& values);

// The comparison of `simulated` with `log` (the part of Replay after Simulate).
std::vector<SignalFit> CompareWithLog(const RobotLog& log, const Simulated& simulated);

}  // namespace plumb

#endif  // PLUMB_INCLUDE_PLUMB_REPLAY_H_
