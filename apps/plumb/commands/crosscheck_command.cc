// plumb crosscheck: the same physics on MuJoCo Warp or MJX as on CPU MuJoCo?

#include <fmt/format.h>

#include <cstdio>

#include "cli_common.h"
#include "plumb/check_table.h"
#include "plumb/crosscheck.h"
#include "plumb/error.h"
#include "plumb/report.h"
#include "plumb/result_json.h"

namespace plumb::cli {
namespace {

struct CrosscheckCommandOptions {
  std::string model;
  std::vector<std::string> sets;
  std::string keyframe;
  StartPose pose;
  std::vector<std::string> randomize, metrics, checks;
  CrosscheckOptions spec;
  bool setup = false;
  std::string format = "table";
  TableDetail detail = TableDetail::kFindings;
  std::string report;
};

int RunCrosscheck(CrosscheckCommandOptions& o, const Context& ctx) {
  internal::RefuseOutputsOntoInputs({{"--report", o.report}}, ModelInputs(o.model, o.pose));
  if (o.setup && o.model.empty()) {
    EngineSetup setup = ReadyEngineSetup(o.spec.engine);  // made on first use
    std::printf("%s\n", setup.python.c_str());
    return kExitOk;
  }
  if (o.model.empty()) {
    throw ArgumentError("model", "",
                        "give the MODEL to check (or --setup alone to make the "
                        "engine's environment)");
  }
  FindEngineSetup(o.spec.engine);  // a bad engine or place for its environment, before any work
  Model model = LoadModel(o.model);
  CrosscheckOptions& spec = o.spec;
  spec.sets = StartAssignments(model, o.keyframe, o.pose, o.sets);
  for (const std::string& r : o.randomize) spec.randomize.push_back(ParseRandomization(model, r));
  for (const std::string& m : o.metrics) spec.metrics.push_back(ParseMetric(model, m));
  if (!o.checks.empty()) spec.checks = o.checks;
  spec.setup = ReadyEngineSetup(spec.engine);
  spec.stop = CommandStop().token();
  CrosscheckReport result = Crosscheck(model, spec);
  if (!o.report.empty()) {
    WriteCrosscheckReport(o.report, model, spec.sets, result, spec.until, ReportInfo{ctx.argv});
    std::fprintf(stderr, "plumb: wrote the report %s\n", o.report.c_str());
  }
  std::string text = o.format == "json" ? WithNotices(CrosscheckToJson(result))
                                        : CrosscheckTable(result, o.detail, kSeeAllRows);
  std::fwrite(text.data(), 1, text.size(), stdout);
  return result.failed() ? kExitCheckFailed : kExitOk;
}

}  // namespace

void SetupCrosscheckCommand(CLI::App& app, Context& ctx) {
  auto o = std::make_shared<CrosscheckCommandOptions>();
  CLI::App* cmd = AddCommand(
      app, "crosscheck",
      "Does a GPU engine (MuJoCo Warp, MJX) compute the same physics as CPU MuJoCo?",
      "Examples:\n"
      "  plumb crosscheck models/pendulum.xml --engine warp --set 'qpos[hinge]=0.7'\n"
      "  plumb crosscheck humanoid.xml --engine mjx --worlds 64 --until 1 \\\n"
      "      --randomize 'body_mass[*]=*U(0.9,1.1)' --report humanoid-mjx.html\n"
      "  plumb crosscheck --setup --engine warp     (make the engine's environment now)\n"
      "Checks: support, stages (one step, stage by stage), trajectory (against the chaos\n"
      "baseline), statistics (two one-sided tests), throughput. The engine runs in its own\n"
      "Python environment, made on first use from PyPI (Warp ~540 MB, MJX ~690 MB).\n"
      "Exit codes: 0 nothing failed, 1 a check failed, 2 bad input, 5 the engine's environment\n"
      "cannot be made, 6 the engine's adapter failed.");
  cmd->add_option("model", o->model, "MJCF (.xml) or binary (.mjb) model file");
  cmd->add_option("--set", o->sets,
                  "PATH=VALUE for the nominal scenario, e.g. 'qpos[hinge]=0.7' (repeatable)")
      ->allow_extra_args(false);
  AddKeyframeOption(cmd, &o->keyframe);
  AddStartPoseOptions(cmd, &o->pose);
  CrosscheckOptions& s = o->spec;
  cmd->add_option("--engine", s.engine, "warp or mjx")
      ->capture_default_str()
      ->check(CLI::IsMember(CrosscheckEngines()));
  cmd->add_option("--device", s.device, "cpu or cuda")
      ->capture_default_str()
      ->check(CLI::IsMember({"cpu", "cuda"}));
  cmd->add_option("--until", s.until, "length of each run, s")->capture_default_str();
  cmd->add_option("--worlds", s.worlds, "N randomized worlds of the statistics check")
      ->capture_default_str()
      ->check(CLI::Range(2, 1 << 20));
  cmd->add_option("--samples", s.samples, "states of the stage check")
      ->capture_default_str()
      ->check(CLI::Range(1, 4096));
  cmd->add_option("--starts", s.starts, "K starts of the trajectory check")
      ->capture_default_str()
      ->check(CLI::Range(1, 4096));
  cmd->add_option("--tol", s.tol,
                  "a signal has parted past tol x max(its swing, 1 m or rad); the statistics "
                  "margin's floor")
      ->capture_default_str();
  cmd->add_option("--margin", s.margin, "equivalence margin, of the CPU metric's spread")
      ->capture_default_str();
  cmd->add_option("--alpha", s.alpha, "level of each one-sided test")->capture_default_str();
  cmd->add_option("--randomize", o->randomize, "PATH=DIST as plumb rollout takes it (repeatable)")
      ->allow_extra_args(false);
  cmd->add_option("--ctrl-noise", s.ctrl_noise, "control noise as plumb rollout takes it (0..1)")
      ->capture_default_str();
  cmd->add_option("--metric", o->metrics, "a metric as plumb rollout takes it (repeatable)")
      ->allow_extra_args(false);
  cmd->add_option("--seed", s.seed, "random seed of the randomized worlds")->capture_default_str();
  cmd->add_option("--threads", s.threads, "threads of plumb's CPU rollouts (0: all cores)")
      ->capture_default_str();
  cmd->add_option("--check", o->checks,
                  "run only these checks: support, stages, trajectory, statistics, throughput "
                  "(repeatable)")
      ->allow_extra_args(false);
  cmd->add_flag("--setup", o->setup,
                "make the engine's Python environment (downloads 0.5-0.7 GB from PyPI); with no "
                "MODEL, only that");
  AddFormatOption(cmd, &o->format, {"table", "json"});
  AddTableDetailOptions(cmd, &o->detail);
  AddReportOption(cmd, &o->report);
  cmd->callback([o, &ctx] { ctx.action = [o, &ctx] { return RunCrosscheck(*o, ctx); }; });
}

}  // namespace plumb::cli
