// The tables of converge, diff, replay and identify (include/plumb/result_table.h).

#include "plumb/result_table.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "core/strings.h"
#include "plumb/error.h"
#include "plumb/model.h"

namespace plumb {
namespace {

// `v` with `spec`, or "-" when it is not finite.
std::string Num(double v, const char* spec) {
  return std::isfinite(v) ? fmt::format(fmt::runtime(spec), v) : std::string("-");
}

std::string ConvergeVerdict(const ConvergenceResult& r) {
  if (!r.ok) return (r.diverged ? "diverged " : "cannot measure ") + r.problem + "\n";
  std::string out = r.estimate.resolved
                        ? fmt::format("observed order  {:.2f} (the integrator's is {:g})\n",
                                      r.estimate.order, r.expected_order)
                        : fmt::format("observed order  unresolved (the integrator's is {:g})\n",
                                      r.expected_order);
  bool measured = r.estimate.extrapolated == r.levels.back().value;
  out += fmt::format("value           {:.15g} ({}: {})\n", r.estimate.extrapolated,
                     measured ? "measured at the finest level" : "an estimate", r.estimate.note);
  out += r.recommended_dt > 0
             ? fmt::format(
                   "recommended dt  {:g} s: the largest tested level with estimated error "
                   "below tol {:g} x scale {:.3g}\n",
                   r.recommended_dt, r.tol, r.scale)
             : std::string(
                   "recommended dt  none (no tested level is shown to meet the tolerance; "
                   "start from a smaller timestep or halve it more times)\n");
  if (!r.caveat.empty()) out += "caveat          " + r.caveat + "\n";
  return out;
}

// Under another MuJoCo than the snapshot's: the upgrade's question, answered in one line.
std::string UpgradeLine(const SnapshotDiff& diff) {
  if (diff.snapshot_mujoco_version == MujocoVersion()) return "";
  bool trajectory = std::any_of(diff.changes.begin(), diff.changes.end(),
                                [](const SnapshotChange& c) { return c.kind == "trajectory"; });
  if (diff.changed()) {
    return fmt::format(
        "upgrade {} -> {}: behaviour changed ({}); see the changes above\n",
        diff.snapshot_mujoco_version, MujocoVersion(),
        trajectory ? "the golden trajectory departs" : "structure or parameters differ");
  }
  return fmt::format(
      "upgrade {} -> {}: same structure and parameters, trajectory within cross-version "
      "round-off (tol {:g})\n",
      diff.snapshot_mujoco_version, MujocoVersion(), diff.tol);
}

std::string EstimatesTable(const IdentifyResult& r, DelayKind delay, std::size_t width) {
  std::string out = fmt::format("{:<{}} {:>12} {:>12} {:>11} {:>25}\n", "parameter", width,
                                "nominal", "estimate", "std error", "95 % interval");
  for (const Estimate& e : r.estimates) {
    std::string interval = std::isfinite(e.std_error)
                               ? fmt::format("[{:.5g}, {:.5g}]", e.value - 1.96 * e.std_error,
                                             e.value + 1.96 * e.std_error)
                               : std::string("-");
    std::string se = r.std_errors.kind == StdErrorKind::kWithheld ? std::string("withheld")
                                                                  : Num(e.std_error, "{:.3g}");
    out += fmt::format("{:<{}} {:>12.6g} {:>12.6g} {:>11} {:>25}{}\n", e.path, width, e.nominal,
                       e.value, se, interval, e.at_bound ? "  (on its bound)" : "");
  }
  if (delay != DelayKind::kNone) {
    out += fmt::format(
        "{:<{}} {:>12} {:>12.6g} {:>11} {:>25}\n",
        delay == DelayKind::kInput ? "input delay [s]" : "sensor delay [s]", width, "0", r.delay,
        "-",
        fmt::format("(resolution {:g} s)", r.delay_scan.size() > 1 ? r.delay_scan[1].first : 0.0));
  }
  if (r.estimates.size() > 1) {
    out += "\ncorrelation\n";
    for (std::size_t i = 0; i < r.estimates.size(); ++i) {
      out += fmt::format("  {:<{}}", r.estimates[i].path, width);
      for (std::size_t j = 0; j <= i; ++j) out += fmt::format(" {:>7.3f}", r.correlation[i][j]);
      out += "\n";
    }
  }
  return out;
}

// What the fit changed, parameter by parameter.
std::string Changes(const IdentifyResult& r) {
  std::string out;
  for (const Estimate& e : r.estimates) {
    if (e.value == e.nominal) continue;
    out += fmt::format("  {}: {:.6g} -> {:.6g}", e.path, e.nominal, e.value);
    if (e.nominal != 0) out += fmt::format(" ({:+.1f} %)", 100 * (e.value / e.nominal - 1));
    out += "\n";
  }
  return out.empty() ? "  (nothing)\n" : out;
}

}  // namespace

std::string ConvergeTable(const ConvergenceResult& r) {
  std::string out = fmt::format("metric {} on {}, over {:g} s\n\n", r.metric, r.model, r.until);
  out += fmt::format("{:>12} {:>22} {:>12} {:>8} {:>12}\n", "dt [s]", "value", "diff", "order",
                     "est. error");
  for (const ConvergenceLevel& l : r.levels) {
    out += fmt::format("{:>12g} {:>22} {:>12} {:>8} {:>12}{}{}\n", l.dt, Num(l.value, "{:.15g}"),
                       Num(l.diff, "{:.3e}"), Num(l.order, "{:.2f}"), Num(l.error, "{:.3e}"),
                       l.roundoff ? "  (diff is round-off)" : "",
                       l.error_is_richardson ? "  (Richardson estimate: no finer level)" : "");
  }
  return out + "\n" + ConvergeVerdict(r);
}

std::string DiffTable(const SnapshotDiff& diff, const std::string& snapshot,
                      const std::string& set_prefix) {
  std::string out;
  if (!diff.sets.empty()) {
    std::vector<std::string> sets;
    for (const std::string& t : diff.sets) sets.push_back(set_prefix + Quoted(t));
    out += "note: the model is simulated with the snapshot's " +
           Join(sets, set_prefix.empty() ? ", " : " ") + "\n";
  }
  for (const std::string& n : diff.notes) out += "note: " + n + "\n";
  if (!diff.compiler.empty()) {
    out += fmt::format(
        "note: {} value(s) that MuJoCo's compiler derives from mesh files (fitted geom size, "
        "frame, bounds) came out differently under {} than under {}; the model did not "
        "change them (the JSON lists them all):\n",
        diff.compiler.size(), MujocoVersion(), diff.snapshot_mujoco_version);
    for (std::size_t i = 0; i < diff.compiler.size() && i < 3; ++i) {
      out += "  " + diff.compiler[i].what + "\n";
    }
    if (diff.compiler.size() > 3) {
      out += fmt::format("  ... and {} more\n", diff.compiler.size() - 3);
    }
  }
  for (const SnapshotChange& c : diff.changes) out += c.what + "\n";
  out += diff.changed()
             ? fmt::format("{} change(s) beyond tol {:g}\n", diff.changes.size(), diff.tol)
             : fmt::format("identical to {} within tol {:g}\n", snapshot, diff.tol);
  return out + UpgradeLine(diff);
}

std::string FitTable(const std::vector<SignalFit>& fits) {
  std::size_t width = 16;
  for (const SignalFit& f : fits) width = std::max(width, f.column.size());
  std::string out = fmt::format("{:<{}} {:>8} {:>12} {:>12} {:>10} {:>8}\n", "signal", width,
                                "samples", "rms error", "max error", "at t [s]", "fit %");
  for (const SignalFit& f : fits) {
    out += fmt::format("{:<{}} {:>8} {:>12.4g} {:>12.4g} {:>10.4f} {:>8.2f}\n", f.column, width,
                       f.samples, f.rms, f.max_abs, f.worst_time, f.fit);
  }
  return out;
}

std::string ReplayTable(const std::string& model, const RobotLog& log, const ReplayOptions& options,
                        const ReplayResult& r) {
  std::string inputs;
  for (const LogSignal& s : log.inputs) inputs += (inputs.empty() ? "" : ", ") + s.column;
  std::string out =
      fmt::format("replay of {} on {}: {:g} s from t = {:g} s; inputs: {}\n", log.source, model,
                  log.end - log.start, log.start, inputs.empty() ? "none" : inputs);
  if (options.window > 0) {
    out += fmt::format("restarted from the logged state every {:g} s\n", options.window);
  }
  if (options.input_delay != 0 || options.sensor_delay != 0) {
    out += fmt::format("input delay {:g} s, sensor delay {:g} s\n", options.input_delay,
                       options.sensor_delay);
  }
  out += "\n" + FitTable(r.signals) + "\n";
  out += fmt::format(
      "overall fit {:.2f} % (mean of the signals; 100: the log exactly, 0: no "
      "better than each signal's mean)\n",
      r.fit);
  for (const std::string& note : r.notes) out += "note: " + note + "\n";
  if (r.simulated.diverged) out += r.simulated.problem + "\n";
  return out;
}

std::string IdentifyTable(const std::string& model, const IdentifyResult& r,
                          const std::vector<RobotLog>& logs, DelayKind delay,
                          const HeldOutLog* validation) {
  long samples = 0;
  for (const RobotLog& log : logs) {
    for (const LogSignal& s : log.measured) samples += static_cast<long>(s.value.size());
  }
  std::string out = fmt::format("identify on {} from {} log(s), {} measured samples\n\n", model,
                                logs.size(), samples);
  std::size_t width = 10;
  for (const Estimate& e : r.estimates) width = std::max(width, e.path.size());
  out += EstimatesTable(r, delay, width);
  out += fmt::format("\nsolver: {}\n{}\n", DescribeSolves(r), DescribeResidualVariance(r));
  if (r.misspecification.detected) out += "WARN misspecified: " + r.misspecification.reason + "\n";
  out += "standard errors: " + r.std_errors.why + "\n";
  out += "\nnoise per signal (rms of the residuals):\n";
  for (std::size_t l = 0; l < logs.size(); ++l) {
    for (std::size_t i = 0; i < logs[l].measured.size(); ++i) {
      out += fmt::format("  {}  {}: {:.4g}\n", logs[l].source, logs[l].measured[i].column,
                         r.noise[l][i]);
    }
  }
  out += "\nfit per log (%): nominal -> fitted\n";
  for (std::size_t l = 0; l < logs.size(); ++l) {
    out += fmt::format("  {}: {:.2f} -> {:.2f}\n", logs[l].source, r.before[l].fit, r.after[l].fit);
  }
  if (validation != nullptr) {
    out +=
        fmt::format("validation on {} (not used for the fit): nominal {:.2f} %, fitted {:.2f} %\n",
                    validation->log->source, validation->nominal.fit, validation->fitted.fit);
  }
  out += "\nchanged:\n" + Changes(r);
  for (const std::string& w : r.warnings) out += "warning: " + w + "\n";
  return out;
}

}  // namespace plumb
