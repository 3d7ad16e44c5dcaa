// Parameter identification (plumb/identify.h): Ceres over the replay error, with our own
// parallel finite-difference Jacobian.

#include "plumb/identify.h"

#include <ceres/ceres.h>
#include <fmt/format.h>

#include <Eigen/Dense>
#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <map>
#include <memory>
#include <set>

#include "core/worker_pool.h"
#include "identify/fit_residuals.h"
#include "identify/identifiability.h"
#include "identify/identify_residuals.h"
#include "io/temp_file.h"
#include "plumb/error.h"
#include "plumb/model_edit.h"
#include "plumb/run.h"
#include "plumb/timing.h"

namespace plumb {
using internal::AddIdentifiabilityWarnings;
using internal::InvertNormal;
using internal::JudgeFit;
using internal::kMostJacobianEntries;
using internal::kMostStartUnknowns;
using internal::NormalInverse;
using internal::Residuals;

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

// Whether a fit keeps `path` at >= 0 though MuJoCo takes a negative value: a damping. MuJoCo
// runs a negative damper (it adds energy: verify plants one), but a fit that lands on one has
// found no damper a robot has (a Go2's calf damping reached -0.34 in a 0.1 s window fit).
bool FitKeepsNonNegative(const Path& path) {
  return path.field == "dof_damping" || path.field == "tendon_damping";
}

// The first solve's weights are the noise the fit leaves within this fraction: then solving
// again with the residuals' noise moved no estimate by more than 0.08 standard errors (the
// arm and the pendulum, several seeds), and it is not done.
constexpr double kWeightsAgree = 0.15;

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
  RequireStepsToReach(options.max_delay, dt, "max_delay");  // counted in a long: 2^53 at most
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

// Throws unless the logs hold more samples than unknowns, and, for an input delay, an
// input to delay.
void RequireEnoughData(const Residuals& f, const std::vector<RobotLog>& logs,
                       const IdentifyOptions& options) {
  if (f.size() <= static_cast<long>(f.parameters())) {
    throw ValueError(fmt::format(
        "the logs hold {} measured samples for {} unknowns ({} parameters and the start states): "
        "fitting needs more samples than unknowns",
        f.size(), f.parameters(), f.physical()));
  }
  if (options.delay == DelayKind::kInput &&
      std::all_of(logs.begin(), logs.end(), [](const RobotLog& l) { return l.inputs.empty(); })) {
    throw ArgumentError(
        "delay", "ctrl",
        "the logs have no input column (ctrl[...], qfrc_applied[...]): there is no input to "
        "delay; name the commanded input with a column map, or estimate no delay");
  }
}

// The warnings about how the fit ended: far from linear, or with the logged start states.
void WarnAboutFit(const Residuals& f, const IdentifyOptions& options, IdentifyResult* result) {
  if (result->relative_offset > kFarFromLinear) {
    result->warnings.push_back(fmt::format(
        "the fit stopped where a Gauss–Newton step would still move the estimates by more than "
        "the noise allows (relative offset {:.2g}, above {:g}): the residuals are far from linear "
        "in the unknowns, and the estimates may sit on a plateau, not at the best fit. {}",
        result->relative_offset, kFarFromLinear,
        options.replay.window > 0
            ? "Shorter replay windows keep each simulation closer to the log."
            : "A simulation of the whole log is too sensitive to its start (contacts, a fall, "
              "chaos): fit in windows that restart from the logged state (a window of 0.25 s, "
              "multiple shooting)."));
  }
  if (!f.fit_starts()) {
    result->warnings.push_back(fmt::format(
        "the start states were taken as logged, not fitted: with these windows and logs they "
        "would add more than {} unknowns, or a Jacobian of more than {} million entries; their "
        "measurement noise may bias the estimates (use longer windows, or fewer samples)",
        kMostStartUnknowns, kMostJacobianEntries >> 20));
  }
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
        if (MustBeNonNegative(p) || FitKeepsNonNegative(p)) f.lo = 0;
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
  const int threads = internal::ThreadsOrAllCores(options.threads);
  Residuals f(model, logs, params, options.replay, threads, options.stop);
  std::size_t n = params.size();
  RequireEnoughData(f, logs, options);
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
  WarnAboutFit(f, options, &result);
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

DelayKind ParseDelayKind(const std::string& text) {
  if (text.empty()) return DelayKind::kNone;
  if (text == "ctrl") return DelayKind::kInput;
  if (text == "sensor") return DelayKind::kSensor;
  throw ArgumentError("delay", Quoted(text),
                      "give ctrl (a delay on the inputs) or sensor (on the measurements)");
}

void CheckIdentifyOptions(const IdentifyOptions& o) {
  CheckReplayOptions(o.replay);
  if (!(o.max_delay > 0 && std::isfinite(o.max_delay))) {
    throw ArgumentError("max_delay", fmt::format("{:g}", o.max_delay),
                        "give a positive number of seconds");
  }
  if (o.threads < 0) {
    throw ArgumentError("threads", std::to_string(o.threads), "give 0 (every core) or more");
  }
  if (o.max_iterations < 1) {
    throw ArgumentError("max_iterations", std::to_string(o.max_iterations), "give 1 or more");
  }
}

std::vector<std::vector<double>> ClassicalCovariance(const IdentifyResult& r) {
  std::vector<std::vector<double>> out = r.correlation;
  for (std::size_t i = 0; i < out.size(); ++i) {
    for (std::size_t j = 0; j < out[i].size(); ++j) {
      out[i][j] *= r.estimates[i].classical_std_error * r.estimates[j].classical_std_error;
    }
  }
  return out;
}

Model FittedModel(const Model& model, const IdentifyResult& result) {
  Model fitted = model.Clone();
  ApplyEstimates(fitted, result);
  return fitted;
}

HeldOutLog ReplayHeldOut(const Model& model, const Model& fitted, const RobotLog& log,
                         const IdentifyOptions& options, const IdentifyResult& result) {
  HeldOutLog out;
  out.log = &log;
  ReplayOptions replay = options.replay;
  if (options.delay == DelayKind::kInput) replay.input_delay = result.delay;
  if (options.delay == DelayKind::kSensor) replay.sensor_delay = result.delay;
  out.nominal = Replay(model, log, options.replay);
  out.fitted = Replay(fitted, log, replay);
  return out;
}

void SaveFittedXml(const std::string& source_xml, const Model& fitted, const IdentifyResult& result,
                   const std::string& out) {
  std::vector<Path> paths;
  for (const Estimate& e : result.estimates) paths.push_back(ResolvePath(fitted, e.path));
  SaveXmlWithParameters(source_xml, fitted, paths, out);
}

void SaveFittedModel(const Model& nominal, const Model& fitted, const IdentifyResult& result,
                     const std::string& out, const std::string& source) {
  if (!source.empty()) return SaveFittedXml(source, fitted, result, out);
  if (nominal.from_xml_file()) return SaveFittedXml(nominal.file(), fitted, result, out);
  // no MJCF of its own (a mujoco.MjModel): the XML MuJoCo parsed last, when it is this model's
  internal::TempFolder dir("plumb-fitted", "the fitted model " + out);
  std::string last = dir.File("last.xml"), why;
  bool saved = nominal.SaveLastXml(last, &why);
  if (saved) why = SourceMismatch(last, nominal);
  if (why.empty()) return SaveFittedXml(last, fitted, result, out);
  throw ValueError(fmt::format(
      "cannot write the fitted model {}: {} has no MJCF file of its own, and the XML MuJoCo "
      "parsed last is not its MJCF ({}). Give the MJCF file the model was compiled from as the "
      "fitted model's source, or load the model from that file",
      out, nominal.file(), saved ? why : "mj_saveLastXML: " + why));
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
