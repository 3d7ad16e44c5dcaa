// plumb audit: the five layers of model acceptance, one section per layer.

#include <fmt/format.h>

#include <cstdio>
#include <filesystem>

#include "cli_common.h"
#include "plumb/accept.h"
#include "plumb/audit.h"
#include "plumb/check_table.h"
#include "plumb/report.h"
#include "plumb/repro.h"
#include "plumb/result_json.h"

namespace plumb::cli {
namespace {

struct AuditCommandOptions {
  std::string model;
  std::vector<std::string> sets;
  std::string keyframe;
  StartPose pose;
  std::string scenario;
  std::string accept;  // --accept FILE.toml
  bool strict = false;
  std::string format = "table";
  std::string repro;
  TableDetail detail = TableDetail::kFindings;
  std::string report;  // --report FILE.html
};

int RunAudit(const AuditCommandOptions& o, const Context& ctx) {
  internal::RefuseOutputsOntoInputs(
      {{"--report", o.report}, {"--repro", o.repro}},
      ModelInputs(o.model, o.pose,
                  {{"the --scenario file", o.scenario}, {"the --accept list", o.accept}}));
  Model model = LoadModel(o.model);
  AuditOptions options;
  // a whole pose is the reference pose's state, before the --set on top
  options.sets = PoseAssignments(model, o.pose);
  for (Assignment& a : ParseAssignments(model, o.sets)) options.sets.push_back(std::move(a));
  options.keyframe = o.keyframe;
  if (!o.scenario.empty()) options.scenario = LoadScenario(model, o.scenario);
  AcceptList accepted = o.accept.empty() ? AcceptList() : LoadAcceptList(o.accept);
  std::string repro_dir =
      o.repro.empty() ? "plumb-repro-" + std::filesystem::path(o.model).stem().string() : o.repro;
  options.keep_diverged = [&](const Model& work, const RunResult& run, const std::string& what) {
    return WriteRepro(work, run, ctx.argv, repro_dir, what);
  };
  options.stop = CommandStop().token();
  std::vector<Assignment> start;
  ReportInfo info{ctx.argv};
  if (!o.report.empty()) {
    // the pictures show the pose the audit judged the model in, drawn while the audit runs
    start = AuditStart(model, options);
    info.ahead = StartPictures(model, start, info);
  }
  AuditReport report = Audit(model, options);
  ApplyAcceptList(accepted, &report.findings);
  if (!o.report.empty()) {
    WriteAuditReport(o.report, model, start, report, info);
    std::fprintf(stderr, "plumb: wrote the report %s\n", o.report.c_str());
  }
  std::string text =
      o.format == "json" ? WithNotices(AuditToJson(report)) : AuditTable(report, o.detail, kSeeAllRows);
  std::fwrite(text.data(), 1, text.size(), stdout);
  return report.Failed(o.strict) ? kExitCheckFailed : kExitOk;
}

}  // namespace

void SetupAuditCommand(CLI::App& app, Context& ctx) {
  auto o = std::make_shared<AuditCommandOptions>();
  CLI::App* cmd = AddCommand(
      app, "audit",
      "Accept a model in five layers: structure, inertia, actuator, contact, behaviour",
      "Examples:\n"
      "  plumb audit /usr/share/mujoco/model/humanoid/humanoid.xml\n"
      "  plumb audit robot.xml --scenario stand.toml --strict --format json\n"
      "  plumb audit robot.xml --strict --accept accepted.toml\n"
      "Scenario files (JSON or TOML): name, duration, keyframe, initial {path = value},\n"
      "controls [{actuator, type = constant|step|ramp|sine, ...}], assertions\n"
      "['xpos[torso][2] > 0.8 during [0, 2]', 'maxabs(qvel[*]) < 50'] (see plumb help audit).\n"
      "Accept lists (TOML), one table per reviewed finding:\n"
      "  [[accept]]\n"
      "  check = \"inertia.shape\"          # the row's id\n"
      "  element = \"body 'base_link'\"     # kind and name, no id; omitted: the whole model\n"
      "  status = \"WARN\"                  # optional: only while it is a WARN\n"
      "  reason = \"CAD inertia checked against the datasheet, 2026-10\"   # required\n"
      "An accepted WARN or FAIL shows as ACCEPT with its reason and fails nothing; an entry that\n"
      "matches no WARN or FAIL is reported as a WARN row accept.stale naming its file and line.\n"
      "Exit codes: 0 nothing failed, 1 a check failed (or warned, with --strict), 2 bad input\n"
      "(also a bad accept list).");
  AddModelOptions(cmd, &o->model, &o->sets, "before the audit");
  AddKeyframeOption(cmd, &o->keyframe);
  AddStartPoseOptions(cmd, &o->pose);
  cmd->add_option("--scenario", o->scenario, "a behaviour scenario (.json or .toml)");
  cmd->add_flag("--strict", o->strict, "exit 1 on warnings too");
  cmd->add_option("--accept", o->accept,
                  "a reviewed list of accepted findings (.toml): they fail nothing (see below)");
  AddFormatOption(cmd, &o->format, {"table", "json"});
  AddTableDetailOptions(cmd, &o->detail);
  cmd->add_option("--repro", o->repro,
                  "folder for the repro of a diverged run (default plumb-repro-<model name>)");
  AddReportOption(cmd, &o->report);
  cmd->callback([o, &ctx] { ctx.action = [o, &ctx] { return RunAudit(*o, ctx); }; });
}

}  // namespace plumb::cli
