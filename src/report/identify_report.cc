// plumb replay --report and plumb identify --report: logged against simulated, the fit.

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "plumb/report.h"
#include "report/page_start.h"

namespace plumb {
namespace {

constexpr std::size_t kMostSignals = 12;   // charts per log

// `v` as long as the log's `n` samples: a simulation that stopped early ends in NaN.
std::vector<double> Padded(const std::vector<double>& v, std::size_t n) {
  std::vector<double> out(v.begin(), v.begin() + static_cast<long>(std::min(n, v.size())));
  out.resize(n, NAN);
  return out;
}

// The fit table of one replay, each row judged against the log's noise.
std::string FitRows(const std::vector<SignalFit>& fits) {
  std::string rows =
      "<table><tr><th></th><th>signal</th><th>samples</th><th>rms error</th><th>max error</th>"
      "<th>at t (s)</th><th>noise</th><th>fit %</th><th>fit % at the noise</th>"
      "<th>fit % beyond the noise</th></tr>\n";
  for (const SignalFit& f : fits) {
    CheckStatus status = FitStatus(f);
    rows += fmt::format(
        "<tr class=\"row-{}\">{}<td>{}</td><td>{}</td><td>{:.4g}</td><td>{:.4g}</td>"
        "<td>{:.4f}</td><td>{:.3g}</td><td>{:.2f}</td><td>{:.2f}</td><td>{:.2f}</td></tr>\n",
        CheckStatusName(status), report::StatusCell(status), report::Escape(f.column), f.samples,
        f.rms, f.max_abs, f.worst_time, f.noise, f.fit, f.noise_fit, f.fit_beyond_noise);
  }
  return rows + "</table>\n" +
         fmt::format(
             "<p>The noise is each signal's, as the log's own differences show it; \"fit % at the "
             "noise\" is what a model that explains all but that noise gets. PASS: the rms error "
             "is within {:g} times the noise; FAIL: beyond that and a fit below {:g} %; else "
             "WARN.</p>\n",
             kFitNoiseMargin, kFitFailPercent);
}

// Logged (points) against one or two simulations (lines), per signal, with +-rms of the
// last simulation dashed.
void SignalCharts(report::Page* page, const RobotLog& log,
                  const std::vector<std::pair<std::string, const ReplayResult*>>& runs) {
  page->BeginGrid();
  for (std::size_t i = 0; i < log.measured.size() && i < kMostSignals; ++i) {
    const LogSignal& s = log.measured[i];
    // every sample: the page draws a long signal from its extremes (report::KeepExtremes)
    const std::vector<double>& t = s.time;
    const std::size_t n = t.size();
    report::Chart chart(s.column + ": logged and simulated", {"t (s)"}, {s.path.text});
    chart.series.push_back(
        {"logged", t, Padded(s.value, n), report::Series::kPoints, "#888", false, "circle"});
    for (const auto& [label, run] : runs) {
      chart.series.push_back({label, t, Padded(run->simulated.values[i], n)});
    }
    const ReplayResult& last = *runs.back().second;
    double rms = last.signals[i].rms;
    if (std::isfinite(rms) && rms > 0) {
      std::vector<double> sim = Padded(last.simulated.values[i], n), hi = sim, lo = sim;
      for (double& v : hi) v += rms;
      for (double& v : lo) v -= rms;
      chart.series.push_back(
          {runs.back().first + " + rms", t, hi, report::Series::kLine, "", true});
      chart.series.push_back(
          {runs.back().first + " - rms", t, lo, report::Series::kLine, "", true});
    }
    chart.how_to_read =
        "Grey points are what was measured; lines are what the model gives from the same start "
        "with the same inputs; dashed lines are the simulation plus and minus its rms error. "
        "Healthy: the points scatter evenly around the line, inside the band. Sick: the line "
        "drifts away with time (a parameter is off: the error grows), lags or leads the points "
        "(a delay), or misses the peaks (damping or inertia).";
    page->Add(chart);
    report::Chart error(s.column + ": simulated - logged", {"t (s)"}, {"error"});
    for (const auto& [label, run] : runs) {
      std::vector<double> e = Padded(run->simulated.values[i], n), logged = Padded(s.value, n);
      for (std::size_t k = 0; k < e.size(); ++k) e[k] -= logged[k];
      error.series.push_back({label, t, e, report::Series::kPoints, "", false, "circle"});
    }
    error.how_to_read =
        "Healthy: noise around zero with no pattern. Sick: a trend, a ramp or a wave in the "
        "error, which is the model's doing, not the sensor's.";
    page->Add(error);
  }
  page->EndGrid();
}

// An estimate's standard error and 95 % interval cells: "withheld" when they are.
std::string ErrorCells(const Estimate& e) {
  if (!std::isfinite(e.std_error)) return "<td>withheld</td><td>-</td>";
  return fmt::format("<td>{:.3g}</td><td>[{:.5g}, {:.5g}]</td>", e.std_error,
                     e.value - 1.96 * e.std_error, e.value + 1.96 * e.std_error);
}

// The estimates with their intervals, the correlation matrix and the warnings.
void EstimatesSection(report::Page* page, const IdentifyResult& r) {
  page->Heading("Estimates");
  page->Paragraph("Standard errors: " + r.std_errors.why + ".",
                  r.std_errors.kind == StdErrorKind::kClassical ? "" : "warn");
  std::string rows = fmt::format(
      "<table><tr><th>parameter</th><th>nominal</th><th>estimate</th><th>std error ({})</th>"
      "<th>95 % interval</th><th>classical std error</th><th>sensitivity</th></tr>\n",
      StdErrorKindName(r.std_errors.kind));
  for (const Estimate& e : r.estimates) {
    rows += fmt::format(
        "<tr><td>{}</td><td>{:.6g}</td><td>{:.6g}{}</td>{}<td>{:.3g}</td><td>{:.3g}</td></tr>\n",
        report::Escape(e.path), e.nominal, e.value, e.at_bound ? " (on its bound)" : "",
        ErrorCells(e), e.classical_std_error, e.sensitivity);
  }
  page->Html(rows + "</table>\n");
  report::Chart bars("Estimates with 95 % intervals, relative to nominal", {"parameter (index)"},
                     {"estimate / nominal"});
  for (std::size_t i = 0; i < r.estimates.size(); ++i) {
    const Estimate& e = r.estimates[i];
    double unit = e.nominal != 0 ? e.nominal : 1;
    double x = static_cast<double>(i);
    bars.series.push_back(
        {e.path, {x}, {e.value / unit}, report::Series::kPoints, "", false, "rectRot"});
    if (!std::isfinite(e.std_error)) continue;  // withheld
    bars.series.push_back(
        {e.path + " 95 %",
         {x, x},
         {(e.value - 1.96 * e.std_error) / unit, (e.value + 1.96 * e.std_error) / unit}});
  }
  bars.how_to_read =
      "Each diamond is an estimate divided by its nominal value (1: the model was right), with "
      "its 95 % interval as a vertical bar (parameters with nominal 0 are shown as they are). "
      "Healthy: short bars. Sick: a bar that spans zero or several times the value (the logs "
      "do not pin the parameter down: see the warnings).";
  page->Add(bars);
  if (r.estimates.size() > 1) {
    std::string table = "<table><tr><th></th>";
    for (const Estimate& e : r.estimates) table += "<th>" + report::Escape(e.path) + "</th>";
    table += "</tr>\n";
    for (std::size_t i = 0; i < r.estimates.size(); ++i) {
      table += "<tr><th>" + report::Escape(r.estimates[i].path) + "</th>";
      for (std::size_t j = 0; j < r.estimates.size(); ++j) {
        double c = r.correlation[i][j];
        int shade = std::isfinite(c) ? static_cast<int>(255 - 155 * std::fabs(c)) : 255;
        table += fmt::format("<td style=\"background: rgb({0},{0},255)\">{1:.3f}</td>", shade, c);
      }
      table += "</tr>\n";
    }
    page->Subheading("Correlation");
    page->Paragraph(
        "Above 0.95 in size, two parameters move the fit together: the logs cannot "
        "tell them apart.");
    page->Html(table + "</table>\n");
  }
  if (!r.warnings.empty()) {
    page->Subheading("Warnings");
    for (const std::string& w : r.warnings) page->Paragraph(w, "warn");
  }
}

// Whether the residuals look like noise: the verdict, and each signal's tests.
void ResidualsSection(report::Page* page, const IdentifyResult& r) {
  const Misspecification& m = r.misspecification;
  page->Heading("Residuals: is the model right?");
  page->Paragraph(
      fmt::format("{}{}.",
                  m.detected ? "WARN misspecified: " : "No misspecification found: ", m.reason),
      m.detected ? "warn" : "");
  std::string rows =
      "<table><tr><th></th><th>log</th><th>signal</th><th>samples</th><th>lag-1 "
      "autocorrelation</th><th>its z</th><th>runs z</th></tr>\n";
  for (const ResidualStructure& s : m.signals) {
    CheckStatus status = s.structured ? CheckStatus::kWarn : CheckStatus::kPass;
    rows += fmt::format(
        "<tr class=\"row-{}\">{}<td>{}</td><td>{}</td><td>{}</td><td>{:.3f}</td><td>{:.1f}</td>"
        "<td>{:.1f}</td></tr>\n",
        CheckStatusName(status), report::StatusCell(status), report::Escape(s.log),
        report::Escape(s.column), s.samples, s.autocorrelation, s.autocorrelation_z, s.runs_z);
  }
  page->Html(rows + "</table>\n");
  page->Paragraph(fmt::format(
      "Each signal's residuals at the optimum, in units of its noise. White noise has a lag-1 "
      "autocorrelation near 0 (z = autocorrelation x sqrt(samples)) and about as many runs of "
      "one sign as chance gives (runs z near 0; negative: long runs, slow structure). A signal "
      "is marked when either |z| exceeds {:.2f}, which all {} signals of white noise do "
      "together with probability {:g}. The fitted model replayed from the logged start costs "
      "{:.6g} against the nominal one's {:.6g} (in units of the noise){}.",
      m.threshold, m.signals.size(), m.false_alarm, m.after_cost, m.before_cost,
      m.worse_than_nominal ? ": worse" : ""));
}

// The cost per iteration and the delay scan.
void SolveSection(report::Page* page, const IdentifyResult& r) {
  page->Heading("The solve");
  page->Paragraph(fmt::format("The {}.", DescribeSolves(r)));
  page->Paragraph(DescribeResidualVariance(r) + ".");
  report::Chart cost("Cost per iteration", {"iteration"}, {"cost", true});
  std::vector<double> first_x, final_x;
  for (std::size_t i = 0; i < r.first_pass_cost.size(); ++i) first_x.push_back(double(i));
  for (std::size_t i = 0; i < r.cost.size(); ++i) final_x.push_back(double(i));
  cost.series.push_back({"first solve (weights: the log's noise)", first_x, r.first_pass_cost,
                         report::Series::kLine});
  cost.series.push_back({r.solved_again ? "solved again (weights: the residuals' noise)"
                                        : "the first solve's end, in the residuals' noise",
                         final_x, r.cost, report::Series::kLine});
  cost.how_to_read =
      "Half the sum of squared weighted residuals after each accepted step. Healthy: a fast "
      "drop, then flat. Sick: still falling at the last iteration (allow more iterations), or "
      "flat from the start far above the number of samples (a wrong model structure).";
  page->BeginGrid();
  page->Add(cost);
  if (!r.delay_scan.empty()) {
    report::Chart scan(fmt::format("Delay: best {:g} s", r.delay), {"delay (s)"},
                       {"cost after fitting", true});
    std::vector<double> d, c;
    for (const auto& [delay, value] : r.delay_scan) d.push_back(delay), c.push_back(value);
    scan.series.push_back({"cost", d, c, report::Series::kPoints, "", false, "circle"});
    scan.how_to_read =
        "The parameters fitted at each delay. Healthy: one clear minimum. Sick: a flat curve "
        "(the logs do not show the delay: add faster inputs).";
    page->Add(scan);
  }
  page->EndGrid();
}

}  // namespace

CheckStatus FitStatus(const SignalFit& f) {
  if (f.rms <= kFitNoiseMargin * f.noise) return CheckStatus::kPass;
  return f.fit >= kFitFailPercent ? CheckStatus::kWarn : CheckStatus::kFail;
}

void WriteReplayReport(const std::string& path, const Model& model, const RobotLog& log,
                       const ReplayResult& result, const ReplayOptions& options,
                       const ReportInfo& info) {
  report::Page page = report::StartPage("replay", model, info);
  page.Meta("log", log.source);
  page.Meta("replay", fmt::format("{:g} s from t = {:g} s; window {}; input delay {:g} s; "
                                  "sensor delay {:g} s",
                                  log.end - log.start, log.start,
                                  options.window > 0 ? fmt::format("{:g} s", options.window)
                                                     : std::string("none"),
                                  options.input_delay, options.sensor_delay));
  page.Heading("How well the model matches the log");
  page.Paragraph(
      fmt::format("Overall fit {:.2f} % (the signals pooled in units of their noise, the "
                  "error beyond it; 100 % is the log up to its noise, 0 % no better than each "
                  "signal's mean).",
                  result.fit));
  page.Html(FitRows(result.signals));
  for (const std::string& note : result.notes) page.Paragraph("Note: " + note);
  if (result.simulated.diverged) page.Paragraph(result.simulated.problem, "fail");
  page.Heading("Signals");
  SignalCharts(&page, log, {{"simulated", &result}});
  report::WritePage(page, path);
}

void WriteIdentifyReport(const std::string& path, const Model& model,
                         const std::vector<RobotLog>& logs, const IdentifyResult& r,
                         const ReportInfo& info, const HeldOutLog* validation) {
  report::Page page = report::StartPage("identify", model, info);
  for (const RobotLog& log : logs) page.Meta("log", log.source);
  EstimatesSection(&page, r);
  ResidualsSection(&page, r);
  SolveSection(&page, r);
  for (std::size_t l = 0; l < logs.size(); ++l) {
    page.Heading("Log " + logs[l].source);
    page.Paragraph(
        fmt::format("Fit: nominal {:.2f} %, fitted {:.2f} %.", r.before[l].fit, r.after[l].fit));
    page.Html(FitRows(r.after[l].signals));
    SignalCharts(&page, logs[l], {{"nominal", &r.before[l]}, {"fitted", &r.after[l]}});
  }
  if (validation != nullptr) {
    page.Heading("Validation on " + validation->log->source);
    page.Paragraph(fmt::format(
        "A log the fit never saw. Fit: nominal {:.2f} %, fitted {:.2f} %. A fit that holds "
        "here describes the robot; one that does not has fitted the noise or the experiment.",
        validation->nominal.fit, validation->fitted.fit));
    page.Html(FitRows(validation->fitted.signals));
    SignalCharts(&page, *validation->log,
                 {{"nominal", &validation->nominal}, {"fitted", &validation->fitted}});
  }
  report::WritePage(page, path);
}

}  // namespace plumb
