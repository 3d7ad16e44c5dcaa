// plumb verify: the main job. One row per check, exit 1 when any check FAILs.

#include <fmt/format.h>

#include <cmath>
#include <cstdio>
#include <optional>

#include "cli_common.h"
#include "plumb/check_table.h"
#include "plumb/report.h"
#include "plumb/result_json.h"
#include "plumb/verify.h"

namespace plumb::cli {
namespace {

struct VerifyCommandOptions {
  std::string model;
  std::vector<std::string> sets;
  std::string keyframe;
  StartPose pose;
  std::string format = "table";
  double tol = VerifyOptions{}.tol;
  std::optional<double> until;  // unset: the default run length
  TableDetail detail = TableDetail::kFindings;
  std::string report;  // --report FILE.html
};

int RunVerify(const VerifyCommandOptions& o, const Context& ctx) {
  internal::RefuseOutputsOntoInputs({{"--report", o.report}}, ModelInputs(o.model, o.pose));
  Model model = LoadModel(o.model);
  VerifyOptions options;
  // the library starts at the reference pose (--keyframe names another), these on top
  options.keyframe = o.keyframe;
  options.sets = StartAssignments(model, "", o.pose, o.sets);
  options.tol = o.tol;
  options.until = o.until;
  options.stop = CommandStop().token();
  ReportInfo info{ctx.argv};
  std::vector<Assignment> start;
  if (!o.report.empty()) {
    // the pictures are drawn while the check runs, from its start, over the run it judges
    start = VerifyStart(model, options);
    info.nominal_until = NominalHorizon(model, options).until;
    info.ahead = StartPictures(model, start, info);
  }
  VerifyReport report = Verify(model, options);
  if (!o.report.empty()) {
    WriteVerifyReport(o.report, model, start, report, info);
    std::fprintf(stderr, "plumb: wrote the report %s\n", o.report.c_str());
  }
  std::string text =
      o.format == "json" ? WithNotices(VerifyToJson(report)) : VerifyTable(report, o.detail, kSeeAllRows);
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
  AddStartPoseOptions(cmd, &o->pose);
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
