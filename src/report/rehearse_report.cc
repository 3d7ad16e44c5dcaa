// A rehearsal's report (plumb bridge with a client): the verdict, the signals over simulated
// time, how the client ended, what plumb saw of its commands, and the bridge's counts.

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <optional>

#include "core/strings.h"
#include "plumb/check_table.h"
#include "plumb/report.h"
#include "report/page_start.h"

namespace plumb {
namespace {

constexpr std::size_t kMostSignals = 12;    // charts of asserted signals
constexpr std::size_t kMotorsPerChart = 4;  // commanded against measured
constexpr std::size_t kMostMotorCharts = 12;
constexpr std::size_t kMostEvents = 200;  // listed
constexpr std::size_t kLineLimit = 400;   // characters of a line of the client's output
const char* const kMotorColours[] = {"#0072B2", "#D55E00", "#009E73", "#CC79A7"};
const char* const kBoundColour = "#cf222e";
const char* const kEventColour = "#6e7781";

// A number for a table cell: "-" when nothing was measured.
std::string Cell(double value, int digits = 4) {
  return std::isfinite(value) ? fmt::format("{:.{}g}", value, digits) : "-";
}

// s as ms, for a period.
std::string Milliseconds(double s) {
  return std::isfinite(s) ? fmt::format("{:.3g} ms", 1e3 * s) : "-";
}

// Rows of a two-column table (what, value), escaped.
std::string KeyValueTable(const std::vector<std::pair<std::string, std::string>>& rows) {
  std::string html = "<table>\n";
  for (const auto& [key, value] : rows) {
    html += "<tr><th>" + report::Escape(key) + "</th><td>" + report::Escape(value) + "</td></tr>\n";
  }
  return html + "</table>\n";
}

// Whether `word`, a path or signal of an assertion, names `signal`: "[*]" in it stands for any
// index ("tracking_error[*]" names "tracking_error[FR_hip]").
bool Names(const std::string& word, const std::string& signal) {
  std::size_t i = 0, k = 0;
  while (i < word.size() && k < signal.size()) {
    if (word.compare(i, 3, "[*]") == 0 && signal[k] == '[') {
      std::size_t close = signal.find(']', k);
      if (close == std::string::npos) return false;
      i += 3;
      k = close + 1;
    } else if (word[i] == signal[k]) {
      ++i, ++k;
    } else {
      return false;
    }
  }
  return i == word.size() && k == signal.size();
}

// An assertion's bound as a line on one of its signals, over its window.
struct BoundLine {
  std::vector<double> levels;  // maxabs: the bound and its negative
  double from, to;
};

// The bound of an assertion row on `signal`, when the row carries one (its reference) and its
// text (plumb's scenario language) holds each sample to it: "PATH > b", min, max, final or
// maxabs of it; a mean holds no sample to its bound. Its window is "during [a, b]" when the
// text has one, else [t0, t1].
std::optional<BoundLine> BoundOf(const CheckRow& row, const std::string& signal, double t0,
                                 double t1) {
  if (row.section != "assert" || !row.reference.known()) return std::nullopt;
  const std::string& text = row.subject;
  std::string word = text.substr(0, text.find_first_of(" <>=!"));
  bool both = false;
  for (const char* reduce : {"min(", "max(", "final(", "maxabs("}) {
    std::size_t n = std::strlen(reduce);
    if (text.compare(0, n, reduce) != 0) continue;
    std::size_t close = text.find(')', n);
    if (close == std::string::npos) return std::nullopt;
    word = text.substr(n, close - n);
    both = std::strcmp(reduce, "maxabs(") == 0;
  }
  if (!Names(word, signal)) return std::nullopt;
  BoundLine line{{row.reference.value}, t0, t1};
  if (both) line.levels.push_back(-row.reference.value);
  std::size_t during = text.find(" during [");
  if (during != std::string::npos) {
    const char* at = text.c_str() + during + 9;
    char* end = nullptr;
    double from = std::strtod(at, &end);
    if (end != at && *end == ',') {
      double to = std::strtod(end + 1, nullptr);
      line.from = std::max(t0, from);
      line.to = to > from ? std::min(t1, to) : t1;  // to < 0: the end of the run
    }
  }
  return line;
}

// Which of a trace's signals were asserted, and each motor's commanded and measured position
// ("q_des[m]" and "q[m]"), by index.
struct TraceParts {
  std::vector<std::size_t> asserted;
  struct Motor {
    std::string name;
    std::size_t commanded, measured;
  };
  std::vector<Motor> motors;
};

TraceParts SplitTrace(const RehearsalTrace& trace) {
  TraceParts parts;
  const std::vector<std::string>& s = trace.signals;
  for (std::size_t i = 0; i < s.size(); ++i) {
    if (s[i].rfind("q_des[", 0) == 0 && s[i].back() == ']') {
      std::string name = s[i].substr(6, s[i].size() - 7);
      auto measured = std::find(s.begin(), s.end(), "q[" + name + "]");
      if (measured != s.end()) {
        parts.motors.push_back({name, i, static_cast<std::size_t>(measured - s.begin())});
      }
    } else if (s[i].rfind("q[", 0) != 0) {
      parts.asserted.push_back(i);
    }
  }
  return parts;
}

// The events as points on a signal: each at the signal's value at the sample nearest it.
report::Series EventPoints(const RehearsalTrace& trace, const std::vector<double>& values) {
  report::Series points("events (listed below)", {}, {}, report::Series::kPoints, kEventColour,
                        false, "triangle");
  for (const auto& [t, what] : trace.events) {
    auto at = std::lower_bound(trace.time.begin(), trace.time.end(), t);
    if (at == trace.time.end()) continue;
    std::size_t k = static_cast<std::size_t>(at - trace.time.begin());
    if (k >= values.size() || !std::isfinite(values[k])) continue;
    points.x.push_back(trace.time[k]);
    points.y.push_back(values[k]);
  }
  return points;
}

// One chart per asserted signal: the signal, the bound of each assertion on it that carries
// one, and the events.
void AssertedCharts(report::Page* page, const RehearsalResult& r, const TraceParts& parts) {
  const RehearsalTrace& trace = r.trace;
  if (trace.time.empty()) return;
  double t0 = trace.time.front(), t1 = trace.time.back();
  page->BeginGrid();
  for (std::size_t n = 0; n < parts.asserted.size() && n < kMostSignals; ++n) {
    std::size_t i = parts.asserted[n];
    const std::string& name = trace.signals[i];
    report::Chart chart(name, {"t (s)"}, {name});
    chart.series.emplace_back(name, trace.time, trace.values[i]);
    for (const CheckRow& row : r.rows) {
      std::optional<BoundLine> bound = BoundOf(row, name, t0, t1);
      if (!bound || !(bound->to >= bound->from)) continue;
      for (double level : bound->levels) {
        chart.series.emplace_back(
            "bound: " + row.subject, std::vector<double>{bound->from, bound->to},
            std::vector<double>{level, level}, report::Series::kLine, kBoundColour, true);
      }
    }
    report::Series events = EventPoints(trace, trace.values[i]);
    if (!events.x.empty()) chart.series.push_back(events);
    chart.how_to_read =
        "The signal at each state the bridge published, over simulated time; a dashed red line "
        "is an assertion's bound over its window, grey triangles the events (faults, watchdog "
        "trips, gamepad presses, the band's release). Healthy: the signal stays on its side of the bound "
        "through the assertion's window. Sick: it crosses the bound, often just after an event "
        "(the client did not cope with it).";
    page->Add(chart);
  }
  page->EndGrid();
  if (parts.asserted.size() > kMostSignals) {
    page->Paragraph(fmt::format("The first {} asserted signals of {} are drawn.", kMostSignals,
                                parts.asserted.size()),
                    "note");
  }
}

// Each motor's commanded position against its measured one, four motors to a chart.
void MotorCharts(report::Page* page, const RehearsalTrace& trace, const TraceParts& parts) {
  if (parts.motors.empty() || trace.time.empty()) return;
  page->BeginGrid();
  std::size_t charts = 0;
  for (std::size_t first = 0; first < parts.motors.size() && charts < kMostMotorCharts;
       first += kMotorsPerChart, ++charts) {
    std::size_t last = std::min(parts.motors.size(), first + kMotorsPerChart);
    std::vector<std::string> names;
    for (std::size_t m = first; m < last; ++m) names.push_back(parts.motors[m].name);
    report::Chart chart("Commanded and measured: " + internal::Join(names, ", "), {"t (s)"},
                        {"position (rad or m)"});
    for (std::size_t m = first; m < last; ++m) {
      const TraceParts::Motor& motor = parts.motors[m];
      const char* colour = kMotorColours[(m - first) % 4];
      chart.series.emplace_back(motor.name + " commanded", trace.time,
                                trace.values[motor.commanded], report::Series::kLine, colour, true);
      chart.series.emplace_back(motor.name + " measured", trace.time, trace.values[motor.measured],
                                report::Series::kLine, colour);
    }
    chart.how_to_read =
        "Dashed: the position the client commanded (q_des) while a command was in force; solid, "
        "the same colour: where the joint was (q). Healthy: the solid line follows the dashed "
        "one closely, with a small lag. Sick: a steady offset (gains too weak for the load, or "
        "the model's own actuator fighting the command), oscillation (gains too stiff for the "
        "model's damping or the command period), or a dashed line beyond what the joint can "
        "reach (a target outside its range).";
    page->Add(chart);
  }
  page->EndGrid();
  if (charts * kMotorsPerChart < parts.motors.size()) {
    page->Paragraph(fmt::format("The first {} motors of {} are drawn.", charts * kMotorsPerChart,
                                parts.motors.size()),
                    "note");
  }
}

// The events with their times.
void EventList(report::Page* page, const RehearsalTrace& trace) {
  page->Subheading("Events");
  if (trace.events.empty()) {
    page->Paragraph("None: no fault, watchdog trip, gamepad press or band release.");
    return;
  }
  std::string html = "<table><tr><th>t (s)</th><th>event</th></tr>\n";
  for (std::size_t i = 0; i < trace.events.size() && i < kMostEvents; ++i) {
    html += fmt::format("<tr><td>{}</td><td>{}</td></tr>\n", Cell(trace.events[i].first, 6),
                        report::Escape(trace.events[i].second));
  }
  page->Html(html + "</table>\n");
  if (trace.events.size() > kMostEvents) {
    page->Paragraph(
        fmt::format("The first {} events of {} are listed.", kMostEvents, trace.events.size()),
        "note");
  }
}

// How the client ended, and its output's last lines: text it printed, shown as text.
void ClientSection(report::Page* page, const ClientEnding& c) {
  page->Heading("The client");
  page->Paragraph("The client " + DescribeClientEnding(c) + ".");
  if (c.last_lines.empty()) {
    page->Paragraph("It printed nothing.", "note");
    return;
  }
  page->Subheading("The last lines of its output");
  std::string pre = "<pre class=\"mono\">";
  for (const std::string& line : c.last_lines) {
    pre += report::Escape(internal::Echo(line, kLineLimit)) + "\n";
  }
  page->Html(pre + "</pre>\n");
}

// What plumb saw of the client's commands: their period, and per motor.
void ViewSection(report::Page* page, const ClientView& v) {
  page->Heading("What plumb saw of the client's commands");
  page->Html(KeyValueTable({
      {"commands (from the controller in charge)", std::to_string(v.commands)},
      {"first command", std::isfinite(v.first_command)
                            ? fmt::format("{:.3g} s after the client started, at t = {} s",
                                          v.first_command, Cell(v.first_command_time))
                            : "none"},
      {"period (wall time): median", Milliseconds(v.period_median)},
      {"period: 95th percentile", Milliseconds(v.period_p95)},
      {"period: worst", Milliseconds(v.period_worst)},
      {"commands per control period", Cell(v.commands_per_period, 3)},
  }));
  if (!v.motors.empty()) {
    std::string html =
        "<table><tr><th>motor</th><th>commands</th><th>targets outside the range</th>"
        "<th>worst, beyond the range</th><th>saturated states</th><th>saturated fraction</th>"
        "<th>worst torque asked</th><th>tracking error rms</th><th>tracking error worst</th>"
        "</tr>\n";
    for (const ClientMotorView& m : v.motors) {
      html += fmt::format(
          "<tr><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td>"
          "<td>{}</td><td>{}</td></tr>\n",
          report::Escape(m.name), m.commands, m.outside_range, Cell(m.worst_outside), m.saturated,
          std::isfinite(m.saturated_fraction) ? fmt::format("{:.1f} %", 100 * m.saturated_fraction)
                                              : "-",
          Cell(m.worst_torque), Cell(m.tracking_rms), Cell(m.tracking_worst));
    }
    page->Html(html + "</table>\n");
    page->Paragraph(
        "Positions in rad (m for a slide), torques in N*m. A saturated state is one where the "
        "law asked for more torque than the motor has; the tracking error is the commanded "
        "position minus the measured one, over the states after the first command.");
  }
  if (!v.unknown_motors.empty()) {
    page->Subheading("Slots the model has no motor for");
    for (const std::string& u : v.unknown_motors) page->Paragraph(u, "warn");
  }
  if (!v.own_pd.empty()) {
    page->Subheading("Actuators of the model with a PD of their own");
    for (const std::string& a : v.own_pd) page->Paragraph(a, "warn");
  }
}

void BridgeSection(report::Page* page, const BridgeStats& b) {
  page->Heading("The bridge");
  std::vector<std::pair<std::string, std::string>> rows = {
      {"simulated time", fmt::format("{:g} s in {} steps", b.time, b.steps)},
      {"realtime factor", Cell(b.realtime_factor, 3)},
      {"commands applied", std::to_string(b.commands)},
      {"states published", std::to_string(b.states)},
      {"dropped: CRC mismatch", std::to_string(b.bad_crc)},
      {"dropped: NaN or infinite values", std::to_string(b.non_finite)},
      {"dropped: from another controller", std::to_string(b.foreign_commands)},
      {"dropped: full command queue (lockstep)", std::to_string(b.queue_drops)},
      {"watchdog trips", std::to_string(b.watchdog_trips)},
      {"injected: commands dropped", std::to_string(b.dropped_commands)},
      {"injected: states dropped", std::to_string(b.dropped_states)},
      {"injected: commands ignored in a pause", std::to_string(b.paused_commands)},
      {"sport-mode states published", std::to_string(b.sport_states)},
      {"secondary IMU states published", std::to_string(b.secondary_imu_states)},
      {"gamepad messages", std::to_string(b.gamepad_messages)},
      {"band released",
       std::isfinite(b.band_released) ? fmt::format("at t = {:g} s", b.band_released) : "no"},
      {"late periods",
       fmt::format("{} (worst {} late)", b.late_periods, Milliseconds(b.worst_lateness))},
      {"late commands (lockstep)",
       fmt::format("{} (longest wait {})", b.late_commands, Milliseconds(b.longest_wait))},
  };
  if (b.diverged) rows.emplace_back("diverged", b.problem);
  page->Html(KeyValueTable(rows));
}

}  // namespace

void WriteRehearsalReport(const std::string& path, const Model& model,
                          const std::vector<Assignment>& start, const RehearsalResult& r,
                          const ReportInfo& info) {
  report::Page page = report::StartPage("bridge", model, info);
  page.Meta("rehearsal", fmt::format("{:g} s simulated, {} states published, {} commands applied",
                                     r.bridge.time, r.bridge.states, r.bridge.commands));
  page.Meta("client", DescribeClientEnding(r.client));
  report::AddModelPictures(&page, model, start, info);

  page.Heading("Verdict");
  page.Paragraph(RehearsalVerdict(r), r.passed() ? "" : "fail");
  const std::vector<CheckRow>& rows = r.rows;  // assert, client, bridge (plumb/rehearse.h)
  page.StatusSummary(CountStatus(rows, CheckStatus::kPass), CountStatus(rows, CheckStatus::kWarn),
                     CountStatus(rows, CheckStatus::kFail), CountStatus(rows, CheckStatus::kSkip));
  page.Html(report::CheckRowsTable(rows, /*findings=*/true));

  page.Heading("Over time");
  TraceParts parts = SplitTrace(r.trace);
  if (r.trace.time.empty()) page.Paragraph("No state was published: nothing to draw.", "note");
  AssertedCharts(&page, r, parts);
  MotorCharts(&page, r.trace, parts);
  EventList(&page, r.trace);

  ClientSection(&page, r.client);
  ViewSection(&page, r.view);
  BridgeSection(&page, r.bridge);
  report::WritePage(page, path);
}

}  // namespace plumb
