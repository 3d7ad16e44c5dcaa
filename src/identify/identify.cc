// Parameter identification (plumb/identify.h): Ceres over the replay error, with our own
// parallel finite-difference Jacobian.

#include "plumb/identify.h"

#include <ceres/ceres.h>
#include <fmt/format.h>

#include <Eigen/Dense>
#include <algorithm>
#include <atomic>
#include <cmath>
#include <list>
#include <map>
#include <memory>
#include <set>
#include <thread>

#include "core/worker_pool.h"
#include "identify/identifiability.h"
#include "identify/identify_residuals.h"
#include "plumb/error.h"
#include "plumb/run.h"

namespace plumb {
namespace {

// Whether MuJoCo refuses a negative value of `path` (a mass, a damping, ...).
bool MustBeNonNegative(const Path& path) {
  try {
    CheckAssignable(path, -1e-3);
  } catch (const ValueError&) {
    return true;
  }
  return false;
}

// The first solve's weights are the noise the fit leaves within this fraction: then solving
// again with the residuals' noise moved no estimate by more than 0.08 standard errors (the
// arm and the pendulum, several seeds), and it is not done.
constexpr double kWeightsAgree = 0.15;

// Start states are fitted while they add at most this many unknowns (windows x logged state
// elements); beyond, the dense Jacobian grows too large and the logged starts are used.
constexpr std::size_t kMostStartUnknowns = 600;
// and while the dense Jacobian (samples x unknowns) stays within 512 MB
constexpr std::size_t kMostJacobianEntries = std::size_t(1) << 26;

// The parameters' values in the worker's model, written from nominal each time so a run
// does not depend on which runs the worker did before (body_mass rescales body_inertia).
class ParameterWriter {
 public:
  ParameterWriter(const Model& nominal, const std::vector<FitParameter>& params)
      : params_(params),
        inertia_(nominal->body_inertia, nominal->body_inertia + 3 * nominal->nbody) {
    for (const FitParameter& p : params) arrays_ = arrays_ || ChangesModelArrays(p.path);
  }

  // Writes parameter values `x` (in scaled units) into the worker's model.
  void Write(WorkerPool::Worker& w, const double* x) const {
    mjModel* m = w.work.get_mutable();
    for (const FitParameter& p : params_) WriteValues(w.work, w.data, p.path, {p.nominal});
    std::copy(inertia_.begin(), inertia_.end(), m->body_inertia);
    for (std::size_t i = 0; i < params_.size(); ++i) {
      WriteValues(w.work, w.data, params_[i].path, {x[i] * params_[i].scale});
    }
    if (arrays_) mj_setConst(m, w.data.get());
  }

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
            const StopToken& stop)
      : logs_(logs),
        writer_(nominal, params),
        pool_(nominal, threads),
        physical_(params.size()),
        n_(params.size()),
        replay_(replay) {
    replay_.stop = stop;  // a replay stops mid-log when asked
    // per log: its windows and each window's start offsets; the samples and their weights
    std::vector<std::size_t> windows_of, offsets_of;
    std::size_t starts = 0;
    for (const RobotLog& log : logs) {
      windows_of.push_back(WindowStarts(nominal, log, replay).size());
      offsets_of.push_back(StartOffsetsPerWindow(nominal, log));
      starts += windows_of.back() * offsets_of.back();
      weights_.emplace_back();
      for (const LogSignal& s : log.measured) {
        m_ += static_cast<long>(s.value.size());
        weights_.back().push_back(NoiseFromDifferences(s.value));
      }
    }
    fit_starts_ = starts <= kMostStartUnknowns &&
                  static_cast<std::size_t>(m_) * (params.size() + starts) <= kMostJacobianEntries;
    std::size_t windows = 0;  // of the logs before this one
    for (std::size_t l = 0; l < logs.size(); ++l) {
      starts_.push_back(n_);
      if (fit_starts_) {
        n_ += windows_of[l] * offsets_of[l];
        colors_ = std::max(colors_, offsets_of[l]);
        for (std::size_t w = 0; w < windows_of[l]; ++w) {
          for (std::size_t j = 0; j < offsets_of[l]; ++j) {
            start_window_.push_back(windows + w);
            start_color_.push_back(j);
          }
        }
      }
      for (const std::vector<std::size_t>& signal : SampleWindows(nominal, logs[l], replay)) {
        for (std::size_t w : signal) row_window_.push_back(windows + w);
      }
      windows += windows_of[l];
    }
    starts_.push_back(n_);
  }

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
  std::vector<std::vector<double>> At(const std::vector<std::vector<double>>& points) {
    std::vector<std::shared_ptr<const std::vector<double>>> errors(points.size());
    std::vector<long> todo;
    for (std::size_t k = 0; k < points.size(); ++k) {
      errors[k] = Remembered(points[k]);
      if (!errors[k]) todo.push_back(static_cast<long>(k));
    }
    runs_ += static_cast<long>(todo.size());
    std::size_t next = 0, emitted = 0;  // results come back in the order asked
    pool_.Stream<std::vector<double>>(
        std::max<std::size_t>(1, todo.size()),
        [&](std::vector<long>* chunk) {
          for (; next < todo.size(); ++next) chunk->push_back(todo[next]);
        },
        [&](WorkerPool::Worker& w, long index, std::vector<double>* e) {
          writer_.Write(w, points[index].data());
          *e = AllErrors(w, points[index]);
          return true;
        },
        [&](const std::vector<double>& e) {
          long k = todo[emitted++];
          errors[k] = std::make_shared<const std::vector<double>>(e);
          Remember(points[k], errors[k]);
        },
        stop(), [] { return Interrupted("plumb identify stopped before the fit finished"); });
    std::vector<std::vector<double>> out;
    out.reserve(points.size());
    for (const auto& e : errors) out.push_back(Weighted(*e));
    return out;
  }

  // Simulated minus logged, per signal of `log`, with the start offsets of x.
  std::vector<std::vector<double>> Errors(WorkerPool::Worker& w, std::size_t log,
                                          const std::vector<double>& x) const {
    std::vector<double> offsets(x.begin() + starts_[log], x.begin() + starts_[log + 1]);
    Simulated s = Simulate(w.work, w.data, logs_[log], replay_, fit_starts_ ? &offsets : nullptr);
    std::vector<std::vector<double>> e(s.values.size());
    for (std::size_t i = 0; i < s.values.size(); ++i) {
      const std::vector<double>& logged = logs_[log].measured[i].value;
      for (std::size_t k = 0; k < logged.size(); ++k) e[i].push_back(s.values[i][k] - logged[k]);
    }
    return e;
  }

 private:
  // Simulated minus logged, every measured sample of every log in order, as they are.
  std::vector<double> AllErrors(WorkerPool::Worker& w, const std::vector<double>& x) const {
    std::vector<double> all;
    all.reserve(m_);
    for (std::size_t log = 0; log < logs_.size(); ++log) {
      for (const std::vector<double>& e : Errors(w, log, x))
        all.insert(all.end(), e.begin(), e.end());
    }
    return all;
  }

  // `errors` over each signal's weight; a divergence (NaN) gives large, finite residuals.
  std::vector<double> Weighted(const std::vector<double>& errors) const {
    std::vector<double> r;
    r.reserve(errors.size());
    std::size_t at = 0;
    for (std::size_t log = 0; log < logs_.size(); ++log) {
      for (std::size_t i = 0; i < logs_[log].measured.size(); ++i) {
        for (std::size_t k = 0; k < logs_[log].measured[i].value.size(); ++k, ++at) {
          double scaled = errors[at] / weights_[log][i];
          r.push_back(std::isfinite(scaled) ? scaled : kDiverged);
        }
      }
    }
    return r;
  }

  std::shared_ptr<const std::vector<double>> Remembered(const std::vector<double>& point) {
    for (auto it = remembered_.begin(); it != remembered_.end(); ++it) {
      if (it->first == point) {
        remembered_.splice(remembered_.begin(), remembered_, it);  // the most recent first
        return remembered_.front().second;
      }
    }
    return nullptr;
  }

  void Remember(const std::vector<double>& point, std::shared_ptr<const std::vector<double>> e) {
    remembered_.emplace_front(point, std::move(e));
    // two Jacobians' points, within a bound on memory
    std::size_t most = std::min(2 * (n_ + 1) + 2,
                                std::max<std::size_t>(2, kRememberBytes / (sizeof(double) * m_)));
    while (remembered_.size() > most) remembered_.pop_back();
  }

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

// The difference step in scaled units (a parameter's nominal value is 1). Forward
// differences, one run per unknown: the standard errors too are taken from them, at the
// optimum, where the runs are already remembered; central differences (step 1e-4) gave
// standard errors within 0.4 % of these on the arm's six parameters, at 2n + 1 runs more.
constexpr double kStep = 1e-6;

// The Jacobian (row-major, residuals x unknowns) at x, with the residuals there: one run per
// model parameter, one per group of start offsets (Residuals::colors), and x itself.
void Jacobian(Residuals& f, const double* x, double* residuals, double* jacobian) {
  std::size_t n = f.parameters(), p = f.physical(), colors = f.colors();
  std::vector<std::vector<double>> points(p + colors + 1, std::vector<double>(x, x + n));
  for (std::size_t j = 0; j < p; ++j) points[j][j] += kStep;
  for (std::size_t u = 0; u + p < n; ++u) points[p + f.start_color(u)][p + u] += kStep;
  long before = f.runs();
  std::vector<std::vector<double>> r = f.At(points);
  f.jacobians += 1;
  f.jacobian_runs += f.runs() - before;
  const std::vector<double>& at = r.back();  // the last point is x itself
  for (long i = 0; i < f.size(); ++i) {
    double* row = jacobian + i * n;
    for (std::size_t j = 0; j < p; ++j) row[j] = (r[j][i] - at[i]) / kStep;
    std::size_t window = f.row_window(i);
    for (std::size_t u = 0; u + p < n; ++u) {
      row[p + u] = f.start_window(u) == window ? (r[p + f.start_color(u)][i] - at[i]) / kStep : 0.0;
    }
  }
  if (residuals != nullptr) std::copy(at.begin(), at.end(), residuals);
}

// How far the Gauss–Newton step from the point of the last Jacobian would still move the fit,
// in the statistical units of Bates and Watts's relative offset: the residuals' part in the
// Jacobian's column space against the rest, sqrt((|Pr|^2 / n) / ((|r|^2 - |Pr|^2) / (m - n))).
// It is the step's length in standard errors over sqrt(n): below kRelativeOffset no estimate
// (start states included) would move by more than kRelativeOffset * sqrt(n) of its standard
// error, and the solve stops there, where Ceres's tolerances would go on polishing digits the
// noise does not support.
double RelativeOffset(const double* jacobian, const double* residuals, long m, std::size_t n) {
  Eigen::Map<const Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>> J(
      jacobian, m, static_cast<long>(n));
  Eigen::Map<const Eigen::VectorXd> r(residuals, m);
  Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(J);
  Eigen::VectorXd step = qr.solve(r);
  double explained = (J * step).squaredNorm(), total = r.squaredNorm();
  double rest = std::max(total - explained, 1e-300 * std::max(total, 1e-300));
  long dof = std::max(1L, m - static_cast<long>(n));
  return std::sqrt((explained / static_cast<double>(n)) / (rest / static_cast<double>(dof)));
}

// Bates and Watts's suggested 0.001 polishes further than a fit to noisy logs can use; at
// 0.01 the remaining step is within a tenth of a standard error for up to 100 unknowns.
constexpr double kRelativeOffset = 0.01;

// Beyond this relative offset where the fit ended, the step left is more than sqrt(n)
// standard errors long: the solver stopped on a plateau of a far from linear problem (a
// Go2's 1 s log simulated whole ends at 10), and the fit says so.
constexpr double kFarFromLinear = 1;

class ReplayCost : public ceres::CostFunction {
 public:
  ReplayCost(Residuals& f, double* offset) : f_(f), offset_(offset) {
    set_num_residuals(static_cast<int>(f.size()));
    mutable_parameter_block_sizes()->push_back(static_cast<int>(f.parameters()));
  }
  // A stop request (Ctrl-C) fails the evaluation; CostLog then aborts the solve, and
  // Identify says it was interrupted.
  bool Evaluate(double const* const* x, double* residuals, double** jacobians) const override {
    try {
      if (jacobians != nullptr && jacobians[0] != nullptr) {
        Jacobian(f_, x[0], residuals, jacobians[0]);
        *offset_ = RelativeOffset(jacobians[0], residuals, f_.size(), f_.parameters());
        return true;
      }
      std::vector<double> at(x[0], x[0] + f_.parameters());
      std::vector<double> r = f_.At({at}).front();
      std::copy(r.begin(), r.end(), residuals);
      return true;
    } catch (const Interrupted&) {
      return false;
    }
  }

 private:
  Residuals& f_;
  double* offset_;  // RelativeOffset at the last Jacobian's point
};

// Records the cost, stops the solve once the relative offset at the current point (Ceres has
// just taken the Jacobian there after a successful step, or kept the point) is small enough,
// and aborts it when a stop is requested.
class CostLog : public ceres::IterationCallback {
 public:
  CostLog(std::vector<double>* cost, const double* offset, const StopToken& stop)
      : cost_(cost), offset_(offset), stop_(stop) {}
  ceres::CallbackReturnType operator()(const ceres::IterationSummary& s) override {
    if (s.iteration == 0 || s.step_is_successful) cost_->push_back(s.cost);
    if (stop_.stop_requested()) return ceres::SOLVER_ABORT;
    return *offset_ <= kRelativeOffset ? ceres::SOLVER_TERMINATE_SUCCESSFULLY
                                       : ceres::SOLVER_CONTINUE;
  }

 private:
  std::vector<double>* cost_;
  const double* offset_;
  const StopToken& stop_;
};

// Solves from x in place; returns Ceres's summary.
ceres::Solver::Summary Solve(Residuals& f, const std::vector<FitParameter>& params,
                             int max_iterations, std::vector<double>* x,
                             std::vector<double>* cost) {
  ceres::Problem::Options problem_options;
  problem_options.cost_function_ownership = ceres::TAKE_OWNERSHIP;
  ceres::Problem problem(problem_options);
  double offset = INFINITY;
  problem.AddResidualBlock(new ReplayCost(f, &offset), nullptr, x->data());
  for (std::size_t i = 0; i < params.size(); ++i) {
    if (std::isfinite(params[i].lo)) {
      problem.SetParameterLowerBound(x->data(), static_cast<int>(i),
                                     params[i].lo / params[i].scale);
    }
    if (std::isfinite(params[i].hi)) {
      problem.SetParameterUpperBound(x->data(), static_cast<int>(i),
                                     params[i].hi / params[i].scale);
    }
  }
  CostLog log(cost, &offset, f.stop());
  ceres::Solver::Options options;
  options.linear_solver_type = ceres::DENSE_QR;
  options.max_num_iterations = max_iterations;
  options.function_tolerance = 1e-10;
  options.parameter_tolerance = 1e-10;
  options.gradient_tolerance = 1e-12;
  // within bounds Ceres would refine each step by a projected line search that wants the
  // Jacobian (a run per unknown) at every trial point, the last one of each solve wasted; each
  // step is projected onto the bounds without it (the same estimates on the arm and the
  // pendulum, 78 runs of the arm's log instead of 88)
  options.max_num_line_search_step_size_iterations = 0;
  options.num_threads = 1;  // the Jacobian's columns are already parallel
  options.logging_type = ceres::SILENT;
  options.callbacks.push_back(&log);
  ceres::Solver::Summary summary;
  ceres::Solve(options, &problem, &summary);
  if (summary.termination_type == ceres::USER_SUCCESS) {
    summary.message = fmt::format(
        "the next step would move the estimates by a relative offset of {:.2g} (Bates and "
        "Watts), within {:g}: less than the noise can tell apart",
        offset, kRelativeOffset);
  }
  if (f.stop().stop_requested())
    throw Interrupted("plumb identify stopped before the fit finished");
  return summary;
}

// The delay: the parameters are fitted at every candidate (whole timesteps up to
// options.max_delay), and the best fit wins; a scan at fixed parameters can settle on a wrong
// delay that the parameters then absorb. Leaves x and f's replay at the best.
void ProfileDelay(Residuals& f, const std::vector<FitParameter>& params,
                  const IdentifyOptions& options, double dt, std::vector<double>* x,
                  IdentifyResult* result) {
  double best_cost = INFINITY;
  std::vector<double> best_x = *x;
  ReplayOptions replay = f.replay(), best_replay = replay;
  long steps = std::max(1L, std::lround(options.max_delay / dt));
  for (long k = 0; k <= steps; ++k) {
    (options.delay == DelayKind::kInput ? replay.input_delay : replay.sensor_delay) = k * dt;
    f.set_delays(replay.input_delay, replay.sensor_delay);
    std::vector<double> at = *x;
    std::vector<double> ignored;
    ceres::Solver::Summary s = Solve(f, params, options.max_iterations, &at, &ignored);
    result->delay_scan.push_back({k * dt, s.final_cost});
    if (s.final_cost < best_cost) best_cost = s.final_cost, best_x = at, best_replay = replay;
  }
  *x = best_x;
  f.set_delays(best_replay.input_delay, best_replay.sensor_delay);
}

// Sets each signal's weight to the rms of its raw residuals at x: its noise, when the model
// fits. Returns those, [log][signal].
std::vector<std::vector<double>> Reweight(Residuals& f, const std::vector<RobotLog>& logs,
                                          const std::vector<double>& x) {
  std::vector<double> r = f.At({x}).front();
  std::vector<std::vector<double>> noise;
  std::size_t at = 0;
  for (std::size_t log = 0; log < logs.size(); ++log) {
    noise.emplace_back();
    for (std::size_t i = 0; i < logs[log].measured.size(); ++i) {
      std::size_t count = logs[log].measured[i].value.size();
      double sum = 0;
      for (std::size_t k = 0; k < count; ++k, ++at) sum += r[at] * r[at];
      double& weight = f.weights()[log][i];
      double rms = std::sqrt(sum / count) * weight;
      // a perfect fit has no noise to weigh by: keep a floor far below any real noise
      weight = std::max(rms, 1e-9 * weight);
      noise.back().push_back(rms);
    }
  }
  return noise;
}

// The Jacobian of everything fitted (residuals x unknowns, in the residuals' units) and the
// residuals, at the optimum: what the standard errors and the residuals' diagnosis read.
struct AtOptimum {
  Eigen::MatrixXd jacobian;
  std::vector<double> residuals;
};

// Classical standard errors and correlations from the Jacobian at x, then the warnings.
AtOptimum Statistics(Residuals& f, const std::vector<FitParameter>& params,
                     const std::vector<double>& x, IdentifyResult* result) {
  std::size_t n = params.size(), all = f.parameters();
  long m = f.size();
  AtOptimum at;
  at.residuals.resize(m);
  std::vector<double> jac(m * all);
  Jacobian(f, x.data(), at.residuals.data(), jac.data());
  result->relative_offset = RelativeOffset(jac.data(), at.residuals.data(), m, all);
  at.jacobian = Eigen::Map<Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>>(
      jac.data(), m, static_cast<long>(all));
  const Eigen::MatrixXd& full = at.jacobian;
  double rss = 0;
  for (double v : at.residuals) rss += v * v;
  result->residuals = m;
  result->residual_variance = rss / static_cast<double>(m - static_cast<long>(all));
  // the covariance of everything fitted (start states included), shown for the parameters
  NormalInverse inverse = InvertNormal(full);
  Eigen::MatrixXd cov = inverse.inverse * result->residual_variance;
  bool singular = inverse.rank < static_cast<long>(all);
  Eigen::MatrixXd J = full.leftCols(static_cast<long>(n));
  result->correlation.assign(n, std::vector<double>(n, NAN));
  for (std::size_t i = 0; i < n; ++i) {
    const FitParameter& p = params[i];
    Estimate e;
    e.path = p.path.text;
    e.nominal = p.nominal;
    e.value = x[i] * p.scale;
    e.lo = p.lo;
    e.hi = p.hi;
    e.sensitivity = J.col(static_cast<long>(i)).norm();
    e.std_error = e.classical_std_error = singular ? NAN : std::sqrt(cov(i, i)) * p.scale;
    double width = std::isfinite(p.hi - p.lo) ? p.hi - p.lo : std::fabs(e.value);
    e.at_bound = std::fabs(e.value - p.lo) <= 1e-9 * std::max(width, 1e-300) ||
                 std::fabs(e.value - p.hi) <= 1e-9 * std::max(width, 1e-300);
    result->estimates.push_back(e);
    for (std::size_t j = 0; j < n; ++j) {
      if (!singular) result->correlation[i][j] = cov(i, j) / std::sqrt(cov(i, i) * cov(j, j));
    }
  }
  AddIdentifiabilityWarnings(params, J, singular, result);
  return at;
}

}  // namespace

std::vector<FitParameter> ResolveFitParameters(const Model& model,
                                               const std::vector<std::string>& fit,
                                               const std::vector<std::string>& bounds) {
  std::vector<FitParameter> params;
  std::set<std::string> seen;
  Data scratch(model);
  for (const std::string& text : fit) {
    for (const Path& block : ExpandPath(model, text)) {
      for (const Path& p : ScalarPaths(block)) {
        if (p.role != Role::kParameter || p.field.rfind("opt.", 0) == 0 || !p.writable) {
          throw ArgumentError(
              "fit", Quoted(text),
              fmt::format("{} is {}, not a model parameter that can be fitted (dof_damping[...], "
                          "body_mass[...], geom_friction[...][0], actuator_gear[...][0], ...)",
                          p.text, p.role == Role::kParameter ? "not writable" : RoleName(p.role)));
        }
        if (!seen.insert(fmt::format("{}:{}", p.field_index, p.first)).second) {
          throw ArgumentError("fit", Quoted(text), p.text + " is fitted twice");
        }
        FitParameter f;
        f.path = p;
        f.nominal = ReadValue(model, scratch, p);
        if (MustBeNonNegative(p)) f.lo = 0;
        params.push_back(f);
      }
    }
  }
  if (params.empty()) throw ArgumentError("fit", "", "name at least one parameter to fit");
  for (const std::string& text : bounds) {
    auto [path_text, range] = SplitAssignment(text, "bounds", "'dof_damping[hinge]=0:1'");
    Path p = ResolvePath(model, path_text);
    auto it = std::find_if(params.begin(), params.end(),
                           [&](const FitParameter& f) { return f.path.text == p.text; });
    if (it == params.end()) {
      throw ArgumentError("bounds", Quoted(text), p.text + " is not among the parameters to fit");
    }
    std::string r(range);
    auto colon = r.find(':');
    char* end = nullptr;
    double lo = colon == std::string::npos ? NAN : std::strtod(r.c_str(), &end);
    bool lo_ok = colon != std::string::npos && end == r.c_str() + colon;
    double hi = colon == std::string::npos ? NAN : std::strtod(r.c_str() + colon + 1, &end);
    bool hi_ok = lo_ok && *end == '\0' && end != r.c_str() + colon + 1;
    if (!lo_ok || !hi_ok || !(lo < hi)) {
      throw ArgumentError("bounds", Quoted(text),
                          fmt::format("give LO:HI with LO < HI, e.g. '{}=0:1'", p.text));
    }
    if (it->nominal < lo || it->nominal > hi) {
      throw ArgumentError("bounds", Quoted(text),
                          fmt::format("the model's {} = {:g} lies outside; start inside the "
                                      "bounds (set {}=... first)",
                                      p.text, it->nominal, p.text));
    }
    it->lo = lo;
    it->hi = hi;
  }
  for (FitParameter& f : params) {
    f.scale = f.nominal != 0                               ? std::fabs(f.nominal)
              : std::isfinite(f.hi) && std::isfinite(f.lo) ? f.hi - f.lo
              : std::isfinite(f.hi)                        ? std::max(std::fabs(f.hi), 1e-3)
                                                           : 1.0;
  }
  return params;
}

IdentifyResult Identify(const Model& model, const std::vector<RobotLog>& logs,
                        const IdentifyOptions& options) {
  std::vector<FitParameter> params = ResolveFitParameters(model, options.fit, options.bounds);
  int threads = options.threads > 0
                    ? options.threads
                    : std::max(1, static_cast<int>(std::thread::hardware_concurrency()));
  Residuals f(model, logs, params, options.replay, threads, options.stop);
  std::size_t n = params.size();
  if (f.size() <= static_cast<long>(f.parameters())) {
    throw ValueError(fmt::format(
        "the logs hold {} measured samples for {} unknowns ({} parameters and the start states): "
        "fitting needs more samples than unknowns",
        f.size(), f.parameters(), n));
  }
  if (options.delay == DelayKind::kInput &&
      std::all_of(logs.begin(), logs.end(), [](const RobotLog& l) { return l.inputs.empty(); })) {
    throw ArgumentError(
        "delay", "ctrl",
        "the logs have no input column (ctrl[...], qfrc_applied[...]): there is no input to "
        "delay; name the commanded input with a column map, or estimate no delay");
  }
  IdentifyResult result;
  double dt = model->opt.timestep;
  std::vector<double> x(f.parameters(), 0.0);  // start offsets from 0: the logged start
  for (std::size_t i = 0; i < n; ++i) x[i] = params[i].nominal / params[i].scale;
  ceres::Solver::Summary first =
      Solve(f, params, options.max_iterations, &x, &result.first_pass_cost);
  result.first_pass_iterations = static_cast<int>(first.iterations.size()) - 1;
  if (options.delay != DelayKind::kNone) ProfileDelay(f, params, options, dt, &x, &result);
  const std::vector<std::vector<double>> first_weights = f.weights();
  result.noise = Reweight(f, logs, x);
  for (std::size_t l = 0; l < first_weights.size(); ++l) {
    for (std::size_t i = 0; i < first_weights[l].size(); ++i) {
      result.weight_change =
          std::max(result.weight_change, std::fabs(result.noise[l][i] / first_weights[l][i] - 1));
    }
  }
  result.solved_again = !(result.weight_change <= kWeightsAgree);
  ceres::Solver::Summary summary = first;
  if (result.solved_again) {
    summary = Solve(f, params, options.max_iterations, &x, &result.cost);
  } else {
    double cost = 0;  // at x in the noise's units (the run is remembered)
    const std::vector<std::vector<double>> at = f.At({x});
    for (double r : at.front()) cost += r * r / 2;
    result.cost = {cost};
  }
  result.delay = options.delay == DelayKind::kInput    ? f.replay().input_delay
                 : options.delay == DelayKind::kSensor ? f.replay().sensor_delay
                                                       : 0;
  result.iterations = result.solved_again ? static_cast<int>(summary.iterations.size()) - 1 : 0;
  result.converged = summary.termination_type == ceres::CONVERGENCE ||
                     summary.termination_type == ceres::USER_SUCCESS;
  result.termination = summary.message;
  AtOptimum at = Statistics(f, params, x, &result);
  result.runs = f.runs();
  result.jacobians = f.jacobians;
  result.jacobian_runs = f.jacobian_runs;
  result.start_unknowns = static_cast<long>(f.parameters() - f.physical());
  result.start_groups = static_cast<long>(f.colors());
  result.runs_per_jacobian = static_cast<long>(f.physical() + f.colors() + 1);
  if (result.relative_offset > kFarFromLinear) {
    result.warnings.push_back(fmt::format(
        "the fit stopped where a Gauss–Newton step would still move the estimates by more than "
        "the noise allows (relative offset {:.2g}, above {:g}): the residuals are far from linear "
        "in the unknowns, and the estimates may sit on a plateau, not at the best fit. {}",
        result.relative_offset, kFarFromLinear,
        options.replay.window > 0
            ? "Shorter windows (--window) keep each simulation closer to the log."
            : "A simulation of the whole log is too sensitive to its start (contacts, a fall, "
              "chaos): fit in windows that restart from the logged state (--window 0.25, "
              "multiple shooting)."));
  }
  if (!f.fit_starts()) {
    result.warnings.push_back(fmt::format(
        "the start states were taken as logged, not fitted: with these windows and logs they "
        "would add more than {} unknowns, or a Jacobian of more than {} million entries; their "
        "measurement noise may bias the estimates (use longer windows, or fewer samples)",
        kMostStartUnknowns, kMostJacobianEntries >> 20));
  }
  Model fitted = model.Clone();
  ApplyEstimates(fitted, result);
  for (const RobotLog& log : logs) {
    result.before.push_back(Replay(model, log, options.replay));
    result.after.push_back(Replay(fitted, log, f.replay()));
  }
  JudgeFit(logs, params, at.jacobian, at.residuals, f.weights(), &result);
  return result;
}

void ApplyEstimates(Model& model, const IdentifyResult& result) {
  std::vector<Assignment> edits;
  for (const Estimate& e : result.estimates) {
    Assignment a;
    a.text = e.path;
    a.path = ResolvePath(model, e.path);
    a.values = {e.value};
    edits.push_back(std::move(a));
  }
  Data scratch(model);
  if (WriteParameters(model, scratch, edits)) mj_setConst(model.get_mutable(), scratch.get());
}

std::string DescribeRuns(const IdentifyResult& r) {
  std::size_t parameters = r.estimates.size();
  std::string starts = r.start_unknowns == 0
                           ? "the logged start states"
                           : fmt::format("{} start-state offset{} in {} group{}", r.start_unknowns,
                                         r.start_unknowns == 1 ? "" : "s", r.start_groups,
                                         r.start_groups == 1 ? "" : "s");
  return fmt::format(
      "the logs simulated {} times in all: {} Jacobian{} of up to {} runs ({} parameter{}, {}, "
      "the point itself) made {}, and the solver's trial points {}",
      r.runs, r.jacobians, r.jacobians == 1 ? "" : "s", r.runs_per_jacobian, parameters,
      parameters == 1 ? "" : "s", starts, r.jacobian_runs, r.runs - r.jacobian_runs);
}

std::string DescribeSolves(const IdentifyResult& r) {
  auto front = [](const std::vector<double>& v) { return v.empty() ? NAN : v.front(); };
  auto back = [](const std::vector<double>& v) { return v.empty() ? NAN : v.back(); };
  std::string second =
      r.solved_again ? fmt::format(
                           "solved again with the noise the residuals show (it differed by up to "
                           "{:.0f} %): {} iterations, cost {:.6g} -> {:.6g} in its units",
                           100 * r.weight_change, r.iterations, front(r.cost), back(r.cost))
                     : fmt::format(
                           "not solved again: the noise the residuals show is within {:.0f} % of "
                           "those weights (up to {:.1f} %), cost {:.6g} in its units",
                           100 * kWeightsAgree, 100 * r.weight_change, back(r.cost));
  return fmt::format(
      "first solve {} iterations, cost {:.6g} -> {:.6g} (each signal weighted by its noise as "
      "the log's differences show it); {}; {} ({}); {}",
      r.first_pass_iterations, front(r.first_pass_cost), back(r.first_pass_cost), second,
      r.converged ? "converged" : "stopped", r.termination, DescribeRuns(r));
}

}  // namespace plumb
