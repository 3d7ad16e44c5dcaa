// The residual vector a fit (plumb identify) minimises: every measured sample of every log
// replayed at given parameters and start offsets, simulated minus logged, over each signal's
// weight, run in parallel and remembered for the points asked again. What the residuals at
// the end say about the model is identify_residuals.h; the solve is identify.cc.

#ifndef PLUMB_SRC_IDENTIFY_FIT_RESIDUALS_H_
#define PLUMB_SRC_IDENTIFY_FIT_RESIDUALS_H_

#include <mujoco/mujoco.h>

#include <cstddef>
#include <list>
#include <memory>
#include <utility>
#include <vector>

#include "core/worker_pool.h"
#include "plumb/identify.h"
#include "plumb/replay.h"

namespace plumb::internal {

// Start states are fitted while they add at most this many unknowns (windows x logged state
// elements); beyond, the dense Jacobian grows too large and the logged starts are used.
inline constexpr std::size_t kMostStartUnknowns = 600;
// and while the dense Jacobian (samples x unknowns) stays within 512 MB
inline constexpr std::size_t kMostJacobianEntries = std::size_t(1) << 26;

// The parameters' values in the worker's model, written from nominal each time so a run
// does not depend on which runs the worker did before (body_mass rescales body_inertia).
class ParameterWriter {
 public:
  ParameterWriter(const Model& nominal, const std::vector<FitParameter>& params);

  // Writes parameter values `x` (in scaled units) into the worker's model.
  void Write(WorkerPool::Worker& w, const double* x) const;

 private:
  const std::vector<FitParameter>& params_;
  std::vector<mjtNum> inertia_;
  bool arrays_ = false;
};

// The residual vector of given parameters: every measured sample of every log, simulated
// minus logged, over the signal's weight. A divergence gives large, finite residuals.
class Residuals {
 public:
  // The start state of every window of every log is fitted too (a logged start carries the
  // measurement noise): those offsets follow the parameters in x, in the logs' units.
  Residuals(const Model& nominal, const std::vector<RobotLog>& logs,
            const std::vector<FitParameter>& params, const ReplayOptions& replay, int threads,
            const StopToken& stop);

  long size() const { return m_; }
  long runs() const { return runs_; }  // how many points At has simulated
  // Jacobian counts its calls and the runs they made here
  long jacobians = 0, jacobian_runs = 0;
  std::size_t parameters() const { return n_; }  // the model's, then the start states
  std::size_t physical() const { return physical_; }
  bool fit_starts() const { return fit_starts_; }
  // The start-state unknowns in groups that one run can perturb together: an offset changes
  // only its own window's samples, so the k-th offset of every window (of every log) is one
  // group, and a Jacobian takes physical() + colors() + 1 runs however many windows there are.
  std::size_t colors() const { return colors_; }
  // Of start unknown u (counted from physical()): its group, and the window (over all logs)
  // whose samples it moves; of residual row i: its window.
  std::size_t start_color(std::size_t u) const { return start_color_[u]; }
  std::size_t start_window(std::size_t u) const { return start_window_[u]; }
  std::size_t row_window(long i) const { return row_window_[static_cast<std::size_t>(i)]; }
  // Changing the delays keeps the windows (and so the start-state offsets) as they are.
  void set_delays(double input, double sensor) {
    replay_.input_delay = input;
    replay_.sensor_delay = sensor;
    remembered_.clear();
  }
  const ReplayOptions& replay() const { return replay_; }
  const StopToken& stop() const { return replay_.stop; }
  std::vector<std::vector<double>>& weights() { return weights_; }

  // Residuals at each of `points` (scaled parameter vectors), in parallel; out[k] has size().
  // The errors of the last points run (two Jacobians' worth) are remembered before they are
  // weighted, and not run again: Ceres asks for the Jacobian at a trial point it has just run,
  // the noise and the second solve's start are taken where the first solve ended, and the
  // standard errors where the fit ended.
  std::vector<std::vector<double>> At(const std::vector<std::vector<double>>& points);

  // Simulated minus logged, per signal of `log`, with the start offsets of x.
  std::vector<std::vector<double>> Errors(WorkerPool::Worker& w, std::size_t log,
                                          const std::vector<double>& x) const;

 private:
  // Simulated minus logged, every measured sample of every log in order, as they are.
  std::vector<double> AllErrors(WorkerPool::Worker& w, const std::vector<double>& x) const;

  // `errors` over each signal's weight; a divergence (NaN) gives large, finite residuals.
  std::vector<double> Weighted(const std::vector<double>& errors) const;

  std::shared_ptr<const std::vector<double>> Remembered(const std::vector<double>& point);

  void Remember(const std::vector<double>& point, std::shared_ptr<const std::vector<double>> e);

  static constexpr double kDiverged = 1e6;
  const std::vector<RobotLog>& logs_;
  ParameterWriter writer_;
  mutable WorkerPool pool_;
  std::size_t physical_, n_;
  std::vector<std::size_t> starts_;  // where each log's start offsets begin in x
  bool fit_starts_ = true;
  std::size_t colors_ = 0;
  std::vector<std::size_t> start_color_, start_window_, row_window_;
  long m_ = 0;
  std::vector<std::vector<double>> weights_;
  ReplayOptions replay_;
  static constexpr std::size_t kRememberBytes = 256u << 20;
  // (point, errors) of the points run last, the most recent first
  std::list<std::pair<std::vector<double>, std::shared_ptr<const std::vector<double>>>> remembered_;
  long runs_ = 0;
};

}  // namespace plumb::internal

#endif  // PLUMB_SRC_IDENTIFY_FIT_RESIDUALS_H_
