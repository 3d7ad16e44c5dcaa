// plumb verify: the main job. One row per check, exit 1 when any check FAILs.

#include <fmt/format.h>

#include <cmath>
#include <cstdio>
#include <nlohmann/json.hpp>
#include <optional>

#include "cli_common.h"
#include "plumb/report.h"
#include "plumb/verify.h"
#include "summary.h"

namespace plumb::cli {
namespace {

struct VerifyCommandOptions {
  std::string model;
  std::vector<std::string> sets;
  std::string keyframe;
  std::string format = "table";
  double tol = 1e-2;
  std::optional<double> until;  // unset: the default run length
  TableDetail detail = TableDetail::kFindings;
  std::string report;  // --report FILE.html
};

std::string Table(const VerifyReport& report, double tol, TableDetail detail) {
  std::vector<CheckRow> rows;
  for (const CheckResult& c : report.checks) {
    CheckRow row{c.status, "", c.id, "", c.detail, "", "", ""};  // about no one element
    row.text = fmt::format("{}  {:<24} {}\n", CheckStatusName(c.status), c.id, c.title);
    if (c.status != CheckStatus::kSkip) {
      std::string numbers = "measured " + (c.measured.empty() ? "-" : c.measured);
      if (!c.reference.empty()) numbers += "   reference " + c.reference;
      if (std::isfinite(c.rel_error)) numbers += fmt::format("   rel. error {:.2g}", c.rel_error);
      row.text += Wrap(numbers, 94, "      ");
    }
    row.text += Wrap(c.detail, 94, "      ");
    rows.push_back(row);
  }
  return CheckTable(
      fmt::format("plumb verify {} (MuJoCo {}, tol {:g})", report.model, MujocoVersion(), tol),
      rows, detail);
}

nlohmann::ordered_json Value(double number, const std::string& text) {
  if (std::isfinite(number)) return number;
  if (text.empty()) return nullptr;
  return text;
}

std::string Json(const VerifyReport& report, double tol) {
  nlohmann::ordered_json j;
  j["model"] = report.model;
  j["mujoco_version"] = MujocoVersion();
  j["tol"] = tol;
  nlohmann::ordered_json checks = nlohmann::ordered_json::array();
  for (const CheckResult& c : report.checks) {
    checks.push_back({{"id", c.id},
                      {"title", c.title},
                      {"status", CheckStatusName(c.status)},
                      {"measured", Value(c.measured_value, c.measured)},
                      {"reference", Value(c.reference_value, c.reference)},
                      {"rel_error", Value(c.rel_error, "")},
                      {"detail", c.detail}});
  }
  j["checks"] = checks;
  j["summary"] = {{"pass", report.Count(CheckStatus::kPass)},
                  {"warn", report.Count(CheckStatus::kWarn)},
                  {"fail", report.Count(CheckStatus::kFail)},
                  {"skip", report.Count(CheckStatus::kSkip)}};
  return j.dump(2) + "\n";
}

int RunVerify(const VerifyCommandOptions& o, const Context& ctx) {
  Model model = LoadModel(o.model);
  VerifyOptions options;
  options.sets = StartAssignments(model, o.keyframe, o.sets);
  options.tol = o.tol;
  options.until = o.until;
  options.stop = CommandStop().token();
  VerifyReport report = Verify(model, options);
  if (!o.report.empty()) {
    ReportInfo info{ctx.argv};
    info.nominal_until = report.figures.t.empty() ? 2.0 : report.figures.t.back();
    WriteVerifyReport(o.report, model, options.sets, report, info);
    std::fprintf(stderr, "plumb: wrote the report %s\n", o.report.c_str());
  }
  std::string text = o.format == "json" ? Json(report, o.tol) : Table(report, o.tol, o.detail);
  std::fwrite(text.data(), 1, text.size(), stdout);
  return report.failed() ? kExitCheckFailed : kExitOk;
}

}  // namespace

void SetupVerifyCommand(CLI::App& app, Context& ctx) {
  auto o = std::make_shared<VerifyCommandOptions>();
  CLI::App* cmd = AddCommand(
      app, "verify",
      "Check that a model's numbers are credible: convergence, energy, analytic physics",
      "Examples:\n"
      "  plumb verify models/pendulum.xml --set 'qpos[hinge]=0.7'\n"
      "  plumb verify /usr/share/mujoco/model/humanoid/humanoid.xml --format json\n"
      "Checks: load, determinism, warnings, convergence, energy; for a single hinge pendulum\n"
      "also analytic.*, the chapter's experiments A/B/C and exercises.\n"
      "Exit codes: 0 nothing failed, 1 a check failed, 2 bad input.");
  AddModelOptions(cmd, &o->model, &o->sets, "for the nominal scenario");
  AddKeyframeOption(cmd, &o->keyframe);
  AddFormatOption(cmd, &o->format, {"table", "json"});
  AddTableDetailOptions(cmd, &o->detail);
  cmd->add_option("--tol", o->tol,
                  "relative tolerance: convergence error and energy drift, of the metric's scale")
      ->capture_default_str();
  cmd->add_option_function<double>(
      "--until", [o](double v) { o->until = v; },
      "nominal run length in s (default 2 s; at most 250 steps for large models)");
  AddReportOption(cmd, &o->report);
  cmd->callback([o, &ctx] { ctx.action = [o, &ctx] { return RunVerify(*o, ctx); }; });
}

}  // namespace plumb::cli
