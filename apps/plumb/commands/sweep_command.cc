// plumb sweep: the Cartesian product of varied parameters, measured in parallel.

#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <optional>

#include "budget.h"
#include "cli_common.h"
#include "plumb/batch.h"
#include "plumb/batch_job.h"
#include "plumb/error.h"
#include "plumb/report.h"
#include "plumb/sample_writer.h"
#include "plumb/store.h"
#include "plumb/sweep.h"
#include "plumb/timing.h"
#include "run_store.h"

namespace plumb::cli {
namespace {

struct SweepOptions {
  std::string model;
  std::vector<std::string> sets;
  std::string keyframe;
  StartPose pose;
  std::vector<std::string> vary;
  std::vector<std::string> metrics;
  int threads = SweepSpec{}.threads;
  double until = SweepSpec{}.until;
  std::string format = "table";
  std::string db;
  double max_seconds = 0;  // --max-seconds: 0 none
  bool resume = false;
  std::string report;  // --report FILE.html
};

// The sweep's cost, said before anything runs: cases, runs, steps, and what the output
// and the store will hold.
std::string CostLine(const Model& model, const SweepOptions& o, const SweepSpec& spec, long cases,
                     std::size_t row_bytes) {
  double dt = RunTimestep(model, spec.sets);
  for (const SweepAxis& axis : spec.axes) {
    if (axis.path.field != "opt.timestep") continue;
    for (std::size_t v = 0; v < axis.size(); ++v) dt = std::min(dt, axis.Value(v).values[0]);
  }
  double steps = 0;
  const std::vector<SweepRun> runs = SweepRuns(spec);  // a case's metrics of one length share one
  for (const SweepRun& run : runs) steps += static_cast<double>(StepsToReach(run.until, dt));
  auto count = [](double x) {
    return x < 1e7 ? fmt::format("{:.0f}", x) : fmt::format("{:.3g}", x);
  };
  double n = static_cast<double>(cases);
  std::string line = fmt::format(
      "sweep of {} case{} x {} metric{}: {} run{}, up to {} steps a case, {} steps in all; about "
      "{} of {} output",
      cases, cases == 1 ? "" : "s", spec.metrics.size(), spec.metrics.size() == 1 ? "" : "s",
      count(n * runs.size()), n * runs.size() == 1 ? "" : "s", count(steps),
      count(steps * n), FormatBytes(n * static_cast<double>(row_bytes)), o.format);
  // a store row: the case's values and metrics as JSON text, plus SQLite's overhead
  if (!o.db.empty()) {
    double row = 60.0 + 24.0 * static_cast<double>(spec.axes.size() + spec.metrics.size());
    line += fmt::format(" and about {} in '{}'", FormatBytes(n * row), o.db);
  }
  return line;
}

// How a sweep's rows are written: a table, CSV or JSON, one case at a time.
class SweepWriter {
 public:
  SweepWriter(const SweepOptions& o, const SweepSpec& spec)
      : o_(o), spec_(spec), json_(o.model, AxisNames(spec), o.metrics) {}

  std::string Header() {
    if (o_.format == "json") return json_.Begin();
    if (o_.format == "csv") {
      std::vector<std::string> header = {"case"};
      for (const SweepAxis& a : spec_.axes) header.push_back(a.path.text);
      header.insert(header.end(), o_.metrics.begin(), o_.metrics.end());
      return CsvLine(header);
    }
    std::string header = fmt::format("{:>6}", "case");
    for (const SweepAxis& a : spec_.axes) {
      // a long range's labels are as wide as its ends or a 15-digit interior value
      std::size_t widest = a.path.text.size();
      std::size_t n = a.size();
      for (std::size_t i = 0; i < std::min<std::size_t>(n, 64); ++i) {
        widest = std::max(widest, a.Label(i).size());
      }
      widest = std::max(widest, a.Label(n - 1).size());
      if (n > 64) widest = std::max<std::size_t>(widest, 17);
      widths_.push_back(std::max<int>(12, static_cast<int>(widest) + 2));
      header += fmt::format("{:>{}}", a.path.text, widths_.back());
    }
    for (const std::string& m : o_.metrics) {
      widths_.push_back(std::max<int>(14, static_cast<int>(m.size()) + 2));
      header += fmt::format("{:>{}}", m, widths_.back());
    }
    return header + "\n";
  }

  std::string Row(const SweepCase& c) {
    if (o_.format == "json") {
      std::vector<double> values;
      for (std::size_t a = 0; a < spec_.axes.size(); ++a) {
        values.push_back(spec_.axes[a].Value(c.choice[a]).values[0]);
      }
      return json_.Row(c.index, values, c.metrics);
    }
    if (o_.format == "csv") {
      std::string line = std::to_string(c.index);
      for (std::size_t a = 0; a < spec_.axes.size(); ++a) {
        line += "," + CsvNumber(spec_.axes[a].Value(c.choice[a]).values[0]);
      }
      for (const Measurement& r : c.metrics) line += "," + (r.ok ? CsvNumber(r.value) : "");
      return line + "\n";
    }
    std::string line = fmt::format("{:>6}", c.index);
    std::size_t w = 0;
    for (std::size_t a = 0; a < spec_.axes.size(); ++a) {
      line += fmt::format("{:>{}}", spec_.axes[a].Label(c.choice[a]), widths_[w++]);
    }
    for (const Measurement& r : c.metrics) {
      // a run that blew up and a metric that does not apply are different findings
      line += r.ok         ? fmt::format("{:>{}.6g}", r.value, widths_[w++])
              : r.diverged ? fmt::format("{:>{}}", "diverged", widths_[w++])
                           : fmt::format("{:>{}}", "n/a", widths_[w++]);
    }
    return line + "\n";
  }

  std::string Footer() const {
    if (o_.format == "json") return json_.End();
    return "";
  }

 private:
  const SweepOptions& o_;
  const SweepSpec& spec_;
  SweepJson json_;
  std::vector<int> widths_;
};

// The spec, validated before the store and the cost line.
SweepSpec MakeSweepSpec(const SweepOptions& o, const Model& model, Notices& notices) {
  SweepSpec spec;
  spec.sets = StartAssignments(model, o.keyframe, o.pose, o.sets);
  spec.threads = o.threads;
  spec.until = o.until;
  return ParseSweepSpec(model, spec, {{}, o.vary, o.metrics, ""}, CliBatchWords(), &notices);
}

int RunSweep(const SweepOptions& o, const Context& ctx) {
  internal::RefuseOutputsOntoInputs({{"--db", o.db}, {"--report", o.report}},
                                    ModelInputs(o.model, o.pose));
  Model model = LoadModel(o.model);
  BatchNotices notices;
  SweepSpec spec = MakeSweepSpec(o, model, notices);
  const long total = CaseCount(spec.axes);
  BatchOrigin origin{o.model, ctx.argv,
                     StartConfig(model, {o.keyframe, o.pose.file, o.pose.qpos, o.sets})};
  BatchJob job(o.db, o.resume, SweepRunInfo(model, spec, origin, o.db), CliBatchWords(),
               &notices);
  SweepWriter writer(o, spec);
  std::string header = writer.Header();
  std::size_t row_bytes =
      o.format == "json" ? 60 + 30 * (spec.axes.size() + spec.metrics.size()) : header.size();
  std::fprintf(stderr, "plumb: %s\n", CostLine(model, o, spec, total, row_bytes).c_str());
  SweepNotices said(spec, &notices, &model);
  job.Resume(total, [](const RolloutResult&) { return true; },
             [&](const RolloutResult& r) { said.SeeStored(r); });
  ProgressBar progress(total - static_cast<long>(job.done().size()), "cases");
  notices.Show(&progress);
  spec.progress = [&](long done, long) { progress.Update(done); };
  // rows reach stdout as they finish, in order, at most ten writes a second
  std::string out = header;
  auto last_write = std::chrono::steady_clock::now();
  auto flush = [&] {
    last_write = std::chrono::steady_clock::now();
    progress.Clear();
    std::string text;
    text.swap(out);
    WriteStdout(text);
  };
  flush();
  std::optional<BatchCollector> batch;
  ReportInfo info{ctx.argv};
  if (!o.report.empty()) {
    batch.emplace(AxisNames(spec), o.metrics);
    info.nominal_until = o.until > 0 ? o.until : 2.0;
    info.ahead = StartPictures(model, spec.sets, info);  // drawn while the cases run
  }
  EtaNote eta("cases", job.stored(), progress);
  auto emit = [&](const SweepCase& c) {
    RolloutResult row = SweepCaseResult(spec, c);
    job.Add(row);
    out += writer.Row(c);
    said.See(c, row);
    if (batch) batch->Add(row.params, row.metrics, row.diverged);
    auto now = std::chrono::steady_clock::now();
    long emitted = job.summary().run_now;
    eta.See(emitted, total - static_cast<long>(job.done().size()) - emitted);
    if (out.size() > (1 << 16) || now - last_write > std::chrono::milliseconds(100)) flush();
  };
  StopTimer budget(CommandStop(), o.max_seconds);  // --max-seconds
  KeepFinishedOnStop(
      [&] { Sweep(model, spec, job.done(), emit, CommandStop().token()); }, progress, job, flush,
      [&] { return fmt::format("the {} finished cases were printed", job.summary().run_now); },
      budget);
  progress.Finish();
  out += writer.Footer();
  flush();
  job.Complete(total);
  said.Finish();
  if (batch) {
    WriteBatchReport(o.report, "sweep", model, spec.sets, *batch, info);
    std::fprintf(stderr, "plumb: wrote the report %s\n", o.report.c_str());
  }
  return kExitOk;
}

}  // namespace

void SetupSweepCommand(CLI::App& app, Context& ctx) {
  auto o = std::make_shared<SweepOptions>();
  CLI::App* cmd = AddCommand(
      app, "sweep", "Measure metrics over the Cartesian product of varied parameters, in parallel",
      "Examples:\n"
      "  plumb sweep models/pendulum.xml --set 'qpos[hinge]=0.7' \\\n"
      "      --vary 'dof_damping[hinge]=0,0.05,1' --metric 'qpos[hinge]@2' --metric energy_drift\n"
      "  plumb sweep models/pendulum.xml --vary 'qpos[hinge]=0.1:2.8:10' \\\n"
      "      --vary opt.integrator=Euler,RK4 --metric 'period(qpos[hinge])' --threads 2\n"
      "Rows come out in case order (first --vary slowest) and are identical for any --threads.\n"
      "A case that diverged shows 'diverged', one whose metric cannot be measured (e.g. no\n"
      "crossings for period) 'n/a'; the reason goes to stderr and the sweep goes on.\n"
      "The cost (cases, steps, output size) is printed before anything runs; rows are printed\n"
      "as they finish, in memory that does not grow with the number of cases. Ctrl-C keeps\n"
      "what finished (exit 130); with --db FILE, --resume runs only the cases not yet stored.");
  AddModelOptions(cmd, &o->model, &o->sets, "applied to every case");
  AddKeyframeOption(cmd, &o->keyframe);
  AddStartPoseOptions(cmd, &o->pose);
  cmd->add_option("--vary", o->vary, "PATH=V1,V2,... or PATH=START:STOP:COUNT (repeatable)")
      ->allow_extra_args(false)
      ->required();
  cmd->add_option("--metric", o->metrics,
                  "PATH@T, period(PATH), maxabs(PATH), energy_drift or state@T (repeatable)")
      ->allow_extra_args(false)
      ->required();
  cmd->add_option("--threads", o->threads, "worker threads")
      ->capture_default_str()
      ->check(CLI::Range(1, 1024));
  cmd->add_option("--until", o->until,
                  "run length in s for period/maxabs/energy_drift (default 20 for period, else 2)");
  AddReportOption(cmd, &o->report);
  AddFormatOption(cmd, &o->format, {"table", "csv", "json"});
  cmd->add_option("--db", o->db, "also record the sweep in this SQLite results store");
  cmd->add_option("--max-seconds", o->max_seconds,
                  "stop after this much wall time, keeping (printing and storing) the cases that "
                  "finished; exit 0 (with --db, --resume goes on)")
      ->check(CLI::PositiveNumber);
  cmd->add_flag("--resume", o->resume,
                "continue the same sweep in --db: skip cases already stored (a fresh start when "
                "it holds no sweep)");
  cmd->callback([o, &ctx] { ctx.action = [o, &ctx] { return RunSweep(*o, ctx); }; });
}

}  // namespace plumb::cli
