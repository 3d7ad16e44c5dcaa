// plumb run: step a model and print or record chosen paths at exact sample times.

#include <fmt/format.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <optional>

#include "budget.h"
#include "cli_common.h"
#include "io/atomic_file.h"
#include "plumb/error.h"
#include "plumb/repro.h"
#include "plumb/run.h"
#include "plumb/sample_writer.h"
#include "plumb/timing.h"
#include "plumb/trajectory.h"
#include "sim/run_notices.h"
#include "sim/start_hints.h"

namespace plumb::cli {
namespace {
using internal::AtomicFile;
using internal::RefuseOutputsOntoInputs;


struct RunOptions {
  std::string model;
  std::vector<std::string> sets;
  std::string keyframe;
  StartPose pose;
  double until = RunSpec{}.until;
  double every = RunSpec{}.every;
  bool every_given = false;  // else about 0.1 s, on whole steps of the timestep the run uses
  std::string columns;
  std::string format = "table";
  std::string output;
  std::string repro;
  RunBudget budget;
};

// The schedule and columns of the run: the timestep --set chooses decides the default
// sampling; --columns expands '*' into scalar columns.
RunSpec MakeRunSpec(const RunOptions& o, const Model& model, double dt) {
  RunSpec spec;
  spec.until = o.until;
  spec.every = RunEvery(o.every_given ? std::optional<double>(o.every) : std::nullopt, dt);
  if (!o.every_given && spec.every != o.every) {
    std::fprintf(stderr, "plumb: sampling every %g s (%ld steps of %g s, the nearest to 0.1 s)\n",
                 spec.every, std::lround(spec.every / dt), dt);
  }
  try {
    spec.columns = RunColumns(model, o.columns.empty() ? std::vector<std::string>{}
                                                       : std::vector<std::string>{o.columns});
  } catch (const PathError& e) {
    throw PathError(std::string("--columns: ") + e.what());
  }
  return spec;
}

// Every warning reaches the user: the per-kind summary, then any other message.
void ReportWarnings(const RunResult& result) {
  internal::AddRunWarnings(result, TakeMujocoWarnings(), &CommandNotices());
}

// The divergence is the news: say it first, then where the repro went and what became of
// the output.
void ReportDivergence(const RunOptions& o, const Context& ctx, const Model& model,
                      const RunResult& result, const std::optional<AtomicFile>& file) {
  std::fprintf(stderr,
               "plumb: error: %s\n"
               "plumb: hint: a timestep that is too large or a mass/inertia that is far off "
               "makes a simulation blow up: halve opt.timestep (--set opt.timestep=...) and "
               "check the compiler's warnings.\n",
               result.divergence->reason.c_str());
  std::string dir =
      o.repro.empty() ? "plumb-repro-" + std::filesystem::path(o.model).stem().string() : o.repro;
  try {
    std::string written = WriteRepro(model, result, ctx.argv, dir);
    std::fprintf(stderr,
                 "plumb: repro folder: %s/ (model, last good and bad state, command line)\n",
                 written.c_str());
  } catch (const IoError& e) {
    std::fprintf(stderr, "plumb: warning: no repro folder: %s (choose one with --repro DIR)\n",
                 e.what());
  }
  if (file && file->direct()) {
    // a FIFO or device cannot be left untouched: it has the samples up to the divergence
    std::fprintf(stderr, "plumb: %s received the samples up to the divergence\n",
                 file->path() == "-" ? "standard output" : file->path().c_str());
  } else if (file) {
    std::fprintf(stderr, "plumb: no output file was written\n");
  }
}

// Runs of at least this many steps are probed for their cost before they start.
constexpr long kProbeAbove = 200'000;

// Says what a long run will cost, and refuses one whose output cannot fit on its disk.
void CheckCost(const RunOptions& o, const RunEstimate& e, bool to_file) {
  if (to_file) {
    std::error_code ec;
    std::filesystem::path dir = std::filesystem::absolute(o.output).parent_path();
    std::filesystem::space_info space = std::filesystem::space(dir, ec);
    if (!ec && e.bytes > static_cast<double>(space.available)) {
      throw IoError(fmt::format(
          "-o {}: this run would write about {:.1f} GB ({}), and {} has {:.1f} GB free. Sample "
          "less often (--every), fewer --columns, a shorter --until, or --max-rows.",
          o.output, e.bytes / 1e9, DescribeEstimate(e, o.format), dir.string(),
          static_cast<double>(space.available) / 1e9));
    }
  }
  if (e.seconds >= 10 || e.bytes >= 1e9) {
    std::fprintf(stderr, "plumb: this run: %s%s\n", DescribeEstimate(e, o.format).c_str(),
                 o.budget.max_seconds > 0 || o.budget.max_rows > 0
                     ? ""
                     : "; --max-seconds or --max-rows bound it");
  }
}

int RunRun(const RunOptions& o, const Context& ctx) {
  RefuseOutputsOntoInputs({{"-o", o.output}, {"--repro", o.repro}}, ModelInputs(o.model, o.pose));
  Model model = LoadModel(o.model);
  Data data(model);
  std::vector<Assignment> sets = StartAssignments(model, o.keyframe, o.pose, o.sets);
  double dt = RunTimestep(model, sets);
  RunSpec spec = MakeRunSpec(o, model, dt);
  // validate the schedule before any output file appears
  Schedule schedule = MakeSchedule(dt, spec.until, spec.every);
  ApplyAssignments(model, data, sets);
  SampleFormat format = o.format == "csv"     ? SampleFormat::kCsv
                        : o.format == "jsonl" ? SampleFormat::kJsonl
                                              : SampleFormat::kTable;
  bool to_file = !o.output.empty() && o.output != "-";
  RunEstimate estimate;
  if (schedule.steps >= kProbeAbove) {
    estimate = EstimateRun(model, sets, spec, format);
    CheckCost(o, estimate, to_file);
  }
  std::optional<AtomicFile> file;
  if (!o.output.empty()) file.emplace(o.output);
  std::unique_ptr<SampleSink> writer = MakeSampleWriter(format, file ? file->stream() : stdout);
  internal::AddStartHints(model, data, "--set", &CommandNotices());
  // a bar only where it cannot interleave with the rows: output to a file or a pipe
  bool bar = estimate.seconds > 2 && (to_file || isatty(fileno(stdout)) == 0);
  BudgetedRun budgeted(*writer, o.budget, estimate.steps, bar);
  budgeted.Watch(spec);
  RunResult result;
  try {
    result = Run(model, data, spec, budgeted);
  } catch (const Interrupted& stopped) {
    if (budgeted.spent().empty()) throw;  // a signal: exit 130, no output file
    if (file) file->Commit();
    std::fprintf(stderr, "plumb: %s spent: stopped %s with %ld rows, every one whole%s\n",
                 budgeted.spent().c_str(), stopped.what() + std::string("interrupted ").size(),
                 budgeted.rows(), file ? ("; " + file->path() + " holds them").c_str() : "");
    ReportWarnings(result);
    return kExitOk;
  }
  ReportWarnings(result);
  if (result.diverged) {
    ReportDivergence(o, ctx, model, result, file);
    return kExitDiverged;
  }
  if (file) file->Commit();
  return kExitOk;
}

}  // namespace

void SetupRunCommand(CLI::App& app, Context& ctx) {
  auto o = std::make_shared<RunOptions>();
  CLI::App* cmd = AddCommand(
      app, "run", "Step a model with mj_step and sample paths over time",
      "Examples:\n"
      "  plumb run models/pendulum.xml --set 'qpos[hinge]=0.7' --until 2 --every 0.1\n"
      "  plumb run models/pendulum.xml --set 'qpos[hinge]=0.7' --format csv -o traj.csv\n"
      "  plumb run humanoid.xml --columns 'time,xpos[torso][2],qpos[root]' --until 1\n"
      "Default columns: time, qpos and qvel of every joint, sensordata of every sensor.\n"
      "Paths: qpos[joint], qvel[joint], ctrl[actuator], xpos[body][2], sensordata[sensor],\n"
      "  opt.timestep, opt.gravity, dof_damping[joint], body_mass[body], ... (any mjModel\n"
      "  or mjData array by name). Angles are radians.\n"
      "Exit codes: 0 ok, 2 bad input, 3 diverged (a repro folder is written), 4 MuJoCo fatal\n"
      "error; plumb --help lists every code.");
  AddModelOptions(cmd, &o->model, &o->sets, "before the run");
  AddKeyframeOption(cmd, &o->keyframe);
  AddStartPoseOptions(cmd, &o->pose);
  cmd->add_option("--until", o->until, "final time in seconds")->capture_default_str();
  cmd->add_option("--every", o->every,
                  "sampling interval in seconds, a whole number of timesteps (default: the whole "
                  "number of steps nearest to 0.1 s)");
  cmd->add_option("--columns", o->columns,
                  "comma-separated paths to sample instead of the defaults ('*' expands rows, "
                  "e.g. 'qpos[*]')");
  AddFormatOption(cmd, &o->format, {"table", "csv", "jsonl"},
                  "table (5 decimals), csv (full precision) or jsonl");
  cmd->add_option("-o,--output", o->output,
                  "write samples to FILE (atomically: complete or not at all; a FIFO or device is "
                  "written directly, a symlink is followed; '-' is stdout)");
  cmd->add_option("--max-seconds", o->budget.max_seconds,
                  "stop after this much wall time, keeping the rows written so far (the output "
                  "is complete up to there; exit 0)")
      ->check(CLI::PositiveNumber);
  cmd->add_option("--max-rows", o->budget.max_rows,
                  "stop after this many sample rows (the first is t = 0), keeping them; exit 0")
      ->check(CLI::PositiveNumber);
  cmd->add_option("--repro", o->repro,
                  "folder for the repro of a diverged run (default plumb-repro-<model name>)");
  cmd->callback([o, cmd, &ctx] {
    o->every_given = cmd->count("--every") > 0;
    ctx.action = [o, &ctx] { return RunRun(*o, ctx); };
  });
}

}  // namespace plumb::cli
