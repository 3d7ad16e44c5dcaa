// plumb results: a results store exported as CSV or JSON.

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <nlohmann/json.hpp>

#include "cli_common.h"
#include "core/strings.h"
#include "plumb/error.h"
#include "plumb/rollout_csv.h"
#include "plumb/sample_writer.h"
#include "plumb/store.h"

namespace plumb::cli {
using internal::Join;

namespace {

struct ResultsOptions {
  std::string file;
  long run = 0;  // 0: every run
  std::string format = "csv";
};

// CSV is one table (one header, a run column): runs whose parameters or metrics differ
// cannot share it, so the user is asked to pick one. @throws ValueError listing the runs.
void RefuseRunsWithDifferentColumns(const std::vector<RunInfo>& runs, const std::string& file) {
  bool same = std::all_of(runs.begin(), runs.end(), [&](const RunInfo& r) {
    return r.parameters == runs[0].parameters && r.metrics == runs[0].metrics;
  });
  if (same) return;
  std::string list;
  for (const RunInfo& r : runs) {
    list += fmt::format("\n  run {} ({}, {} rollouts): parameters {}; metrics {}", r.id, r.kind,
                        r.count, r.parameters.empty() ? "none" : Join(r.parameters, ", "),
                        r.metrics.empty() ? "none" : Join(r.metrics, ", "));
  }
  throw ValueError(
      fmt::format("'{}' holds {} runs with different columns, which one CSV table cannot hold:{}\n"
                  "Export one run with --run N (e.g. plumb results {} --run {}), or every run with "
                  "--format json.",
                  file, runs.size(), list, file, runs.back().id));
}

int RunResults(const ResultsOptions& o) {
  if (!std::ifstream(o.file)) throw IoError("no results store '" + o.file + "'.");
  ResultsStore store(o.file, ResultsStore::Mode::kReadOnly);
  std::vector<RunInfo> runs = store.Runs();
  if (o.run != 0) {
    runs.erase(
        std::remove_if(runs.begin(), runs.end(), [&](const RunInfo& r) { return r.id != o.run; }),
        runs.end());
    if (runs.empty()) throw ValueError(fmt::format("--run {}: no such run in '{}'", o.run, o.file));
  }
  std::string out;
  if (o.format == "json") {
    nlohmann::ordered_json j = nlohmann::ordered_json::array();
    for (const RunInfo& run : runs) {
      nlohmann::ordered_json rows = nlohmann::ordered_json::array();
      for (const RolloutResult& r : store.Results(run.id)) {
        nlohmann::ordered_json p = nlohmann::ordered_json::object(), m = p;
        for (std::size_t k = 0; k < r.params.size() && k < run.parameters.size(); ++k) {
          p[run.parameters[k]] = r.params[k];
        }
        for (std::size_t k = 0; k < r.metrics.size() && k < run.metrics.size(); ++k) {
          m[run.metrics[k]] = std::isnan(r.metrics[k]) ? nlohmann::ordered_json(nullptr)
                                                       : nlohmann::ordered_json(r.metrics[k]);
        }
        nlohmann::ordered_json row = {
            {"rollout", r.index}, {"params", p}, {"metrics", m}, {"diverged", r.diverged}};
        if (r.diverged) row["diverged_time"] = r.diverged_time;
        if (!r.problem.empty()) row["problem"] = r.problem;
        if (!r.warnings.empty()) row["warnings"] = r.warnings;
        rows.push_back(row);
      }
      j.push_back({{"run", run.id},
                   {"kind", run.kind},
                   {"command", run.command},
                   {"model_file", run.model_file},
                   {"model_hash", run.model_hash},
                   {"plumb_version", run.plumb_version},
                   {"mujoco_version", run.mujoco_version},
                   {"started", run.started},
                   {"finished", run.finished},
                   {"count", run.count},
                   {"rollouts", rows}});
    }
    out = j.dump(2) + "\n";
  } else if (!runs.empty()) {
    RefuseRunsWithDifferentColumns(runs, o.file);
    std::vector<std::string> header = {"run"};
    for (const std::string& c : RolloutCsvColumns(runs[0].parameters, runs[0].metrics)) {
      header.push_back(c);
    }
    out = CsvLine(header);
    for (const RunInfo& run : runs) {
      for (const RolloutResult& r : store.Results(run.id)) {
        out += std::to_string(run.id) + "," + RolloutCsvRow(r);
      }
    }
  }
  std::fwrite(out.data(), 1, out.size(), stdout);
  return kExitOk;
}

}  // namespace

void SetupResultsCommand(CLI::App& app, Context& ctx) {
  auto o = std::make_shared<ResultsOptions>();
  CLI::App* results = AddCommand(
      app, "results", "Export a results store as CSV or JSON",
      "Example:\n  plumb results rollouts.sqlite --format csv > rollouts.csv\n"
      "CSV is one table with a run column: one header, every row the same width. Runs whose\n"
      "parameters or metrics differ are exported one at a time with --run N, or all with JSON.");
  results->add_option("file", o->file, "the SQLite results store")->required();
  results->add_option(
      "--run", o->run,
      "only this run id (default: every run; CSV needs runs with the same columns)");
  AddFormatOption(results, &o->format, {"csv", "json"});
  results->callback([o, &ctx] { ctx.action = [o] { return RunResults(*o); }; });
}

}  // namespace plumb::cli
