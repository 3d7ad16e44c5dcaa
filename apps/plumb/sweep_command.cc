// plumb sweep: the Cartesian product of varied parameters, measured in parallel.

#include <fmt/format.h>

#include <cmath>
#include <cstdio>
#include <nlohmann/json.hpp>

#include "cli_common.h"
#include "core/version.h"
#include "plumb/error.h"
#include "plumb/output.h"
#include "plumb/store.h"
#include "plumb/sweep.h"

namespace plumb::cli {
namespace {

struct SweepOptions {
  std::string model;
  std::vector<std::string> sets;
  std::string keyframe;
  std::vector<std::string> vary;
  std::vector<std::string> metrics;
  int threads = 1;
  double until = 0;
  std::string format = "table";
  std::string db;
};

// Records a finished sweep in the results store: one run, one case per combination.
void Store(const SweepOptions& o, const Context& ctx, const SweepSpec& spec,
           const std::vector<SweepCase>& cases) {
  ResultsStore store(o.db);
  RunInfo info;
  info.kind = "sweep";
  info.model_file = o.model;
  info.model_hash = HashFile(o.model);
  info.config = "sweep model=" + info.model_hash;
  if (!o.keyframe.empty()) info.config += " keyframe=" + o.keyframe;
  for (const std::string& s : o.sets) info.config += " set=" + s;
  for (const std::string& v : o.vary) info.config += " vary=" + v;
  for (const std::string& m : o.metrics) info.config += " metric=" + m;
  std::vector<std::string> quoted;
  for (const std::string& a : ctx.argv) quoted.push_back(ShellQuote(a));
  info.command = fmt::format("{}", fmt::join(quoted, " "));
  info.plumb_version = PLUMB_VERSION;
  info.mujoco_version = MujocoVersion();
  for (const SweepAxis& a : spec.axes) info.parameters.push_back(a.path.text);
  info.metrics = o.metrics;
  info.count = static_cast<long>(cases.size());
  long run = store.BeginRun(info);
  for (const SweepCase& c : cases) {
    RolloutResult r;
    r.index = c.index;
    for (std::size_t a = 0; a < spec.axes.size(); ++a) {
      r.params.push_back(spec.axes[a].values[c.choice[a]].values[0]);
    }
    for (const Measurement& m : c.metrics) {
      r.metrics.push_back(m.ok ? m.value : NAN);
      if (!m.ok) {
        r.diverged = r.diverged || m.diverged;
        r.problem += (r.problem.empty() ? "" : "; ") + m.problem;
      }
    }
    store.Add(run, r);
  }
  store.FinishRun(run);
}

int RunSweep(const SweepOptions& o, const Context& ctx) {
  Model model = LoadModel(o.model);
  SweepSpec spec;
  spec.sets = StartAssignments(model, o.keyframe, o.sets);
  for (const std::string& v : o.vary) spec.axes.push_back(ParseSweepAxis(model, v));
  for (const std::string& m : o.metrics) spec.metrics.push_back(ParseMetric(model, m));
  spec.threads = o.threads;
  spec.until = o.until;
  long total = CaseCount(spec.axes);
  ProgressBar progress(total, "cases");
  spec.progress = [&](long done, long) { progress.Update(done); };
  std::vector<SweepCase> cases = Sweep(model, spec);
  progress.Finish();
  if (!o.db.empty()) Store(o, ctx, spec, cases);

  long failed = 0;
  std::string out;
  if (o.format == "json") {
    nlohmann::ordered_json j;
    j["model"] = o.model;
    nlohmann::ordered_json axes = nlohmann::ordered_json::array();
    for (const SweepAxis& a : spec.axes) axes.push_back(a.path.text);
    j["vary"] = axes;
    j["metrics"] = o.metrics;
    nlohmann::ordered_json rows = nlohmann::ordered_json::array();
    for (const SweepCase& c : cases) {
      nlohmann::ordered_json values, metrics, problems = nlohmann::ordered_json::object();
      for (std::size_t a = 0; a < spec.axes.size(); ++a) {
        values[spec.axes[a].path.text] = spec.axes[a].values[c.choice[a]].values[0];
      }
      for (std::size_t m = 0; m < c.metrics.size(); ++m) {
        const Measurement& r = c.metrics[m];
        metrics[o.metrics[m]] = r.ok ? nlohmann::ordered_json(r.value) : nullptr;
        if (!r.ok) problems[o.metrics[m]] = r.problem;
      }
      nlohmann::ordered_json row = {{"case", c.index}, {"values", values}, {"metrics", metrics}};
      if (!problems.empty()) row["problems"] = problems;
      rows.push_back(row);
    }
    j["cases"] = rows;
    out = j.dump(2) + "\n";
  } else if (o.format == "csv") {
    std::vector<std::string> header = {"case"};
    for (const SweepAxis& a : spec.axes) header.push_back(a.path.text);
    header.insert(header.end(), o.metrics.begin(), o.metrics.end());
    out = CsvHeader(header);
    for (const SweepCase& c : cases) {
      out += std::to_string(c.index);
      for (std::size_t a = 0; a < spec.axes.size(); ++a) {
        out += "," + CsvNumber(spec.axes[a].values[c.choice[a]].values[0]);
      }
      for (const Measurement& r : c.metrics) out += "," + (r.ok ? CsvNumber(r.value) : "");
      out += "\n";
    }
  } else {
    std::vector<int> widths;
    std::string header = fmt::format("{:>6}", "case");
    for (const SweepAxis& a : spec.axes) {
      int widest = static_cast<int>(a.path.text.size());
      for (const std::string& label : a.labels) widest = std::max<int>(widest, label.size());
      widths.push_back(std::max(12, widest + 2));
      header += fmt::format("{:>{}}", a.path.text, widths.back());
    }
    for (const std::string& m : o.metrics) {
      widths.push_back(std::max<int>(14, m.size() + 2));
      header += fmt::format("{:>{}}", m, widths.back());
    }
    out = header + "\n";
    for (const SweepCase& c : cases) {
      std::string line = fmt::format("{:>6}", c.index);
      std::size_t w = 0;
      for (std::size_t a = 0; a < spec.axes.size(); ++a) {
        line += fmt::format("{:>{}}", spec.axes[a].labels[c.choice[a]], widths[w++]);
      }
      for (const Measurement& r : c.metrics) {
        // a run that blew up and a metric that does not apply are different findings
        line += r.ok         ? fmt::format("{:>{}.6g}", r.value, widths[w++])
                : r.diverged ? fmt::format("{:>{}}", "diverged", widths[w++])
                             : fmt::format("{:>{}}", "n/a", widths[w++]);
      }
      out += line + "\n";
    }
  }
  for (const SweepCase& c : cases) {
    for (std::size_t m = 0; m < c.metrics.size(); ++m) {
      if (c.metrics[m].ok) continue;
      ++failed;
      std::fprintf(stderr, "plumb: case %ld, %s: %s\n", c.index, o.metrics[m].c_str(),
                   c.metrics[m].problem.c_str());
    }
  }
  std::fwrite(out.data(), 1, out.size(), stdout);
  if (failed > 0) {
    std::fprintf(stderr, "plumb: %ld of %ld measurements could not be made (see above)\n", failed,
                 total * static_cast<long>(spec.metrics.size()));
  }
  return kExitOk;
}

}  // namespace

void SetupSweepCommand(CLI::App& app, Context& ctx) {
  auto o = std::make_shared<SweepOptions>();
  CLI::App* cmd = app.add_subcommand(
      "sweep", "Measure metrics over the Cartesian product of varied parameters, in parallel");
  cmd->footer(
      "Examples:\n"
      "  plumb sweep models/pendulum.xml --set 'qpos[hinge]=0.7' \\\n"
      "      --vary 'dof_damping[hinge]=0,0.05,1' --metric 'qpos[hinge]@2' --metric energy_drift\n"
      "  plumb sweep models/pendulum.xml --vary 'qpos[hinge]=0.1:2.8:10' \\\n"
      "      --vary opt.integrator=Euler,RK4 --metric 'period(qpos[hinge])' --threads 2\n"
      "Rows come out in case order (first --vary slowest) and are identical for any --threads.\n"
      "A case that diverged shows 'diverged', one whose metric cannot be measured (e.g. no\n"
      "crossings for period) 'n/a'; the reason goes to stderr and the sweep goes on.");
  AddModelOptions(cmd, &o->model, &o->sets, "applied to every case");
  AddKeyframeOption(cmd, &o->keyframe);
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
  cmd->add_option("--format", o->format, "table, csv or json")
      ->check(CLI::IsMember({"table", "csv", "json"}))
      ->capture_default_str();
  cmd->add_option("--db", o->db, "also record the sweep in this SQLite results store");
  cmd->callback([o, &ctx] { ctx.action = [o, &ctx] { return RunSweep(*o, ctx); }; });
}

}  // namespace plumb::cli
