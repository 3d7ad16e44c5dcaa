// plumb rollout: many runs with domain randomization, deterministic for any threads.

#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <optional>
#include <utility>

#ifdef __GLIBC__
#include <malloc.h>
#endif

#include "budget.h"
#include "cli_common.h"
#include "core/strings.h"
#include "plumb/batch.h"
#include "plumb/batch_job.h"
#include "plumb/error.h"
#include "plumb/mpi_rollout.h"
#include "plumb/report.h"
#include "plumb/rollout.h"
#include "plumb/rollout_csv.h"
#include "plumb/sample_writer.h"
#include "plumb/store.h"
#include "run_store.h"

namespace plumb::cli {
namespace {

struct RolloutOptions {
  std::string model;
  std::vector<std::string> sets;
  std::string keyframe;
  StartPose pose;
  long count = 100;  // the CLI's own: plumb.rollout takes count as a required argument
  double until = RolloutSpec{}.until;
  int threads = RolloutSpec{}.threads;
  std::uint64_t seed = RolloutSpec{}.seed;
  std::vector<std::string> randomize;
  double ctrl_noise = RolloutSpec{}.ctrl_noise;
  std::vector<std::string> metrics;
  std::string format = "table";
  std::string shard;
  std::string db;
  double max_seconds = 0;  // --max-seconds: 0 none
  bool resume = false;
  std::string report;  // --report FILE.html
};

// The Slurm job array's task id and count as the shard, when --shard is absent.
void ShardFromSlurm(RolloutSpec* spec) {
  // array ids run from SLURM_ARRAY_TASK_MIN (often 1, as in --array=1-8), not from 0
  const char* id = std::getenv("SLURM_ARRAY_TASK_ID");
  const char* count = std::getenv("SLURM_ARRAY_TASK_COUNT");
  const char* min = std::getenv("SLURM_ARRAY_TASK_MIN");
  if (!id || !count) return;
  std::optional<long> i = internal::ParseIndex(id), lowest = internal::ParseIndex(min ? min : "0");
  if (!i || !lowest || *i < *lowest) {
    throw ValueError(fmt::format(
        "Slurm: SLURM_ARRAY_TASK_ID={} with SLURM_ARRAY_TASK_MIN={} is not a task of the "
        "array; pass --shard I/N explicitly.",
        id, min ? min : "(unset)"));
  }
  try {
    ParseShard(std::to_string(*i - *lowest) + "/" + count, spec);
  } catch (const ArgumentError&) {
    // the user passed no --shard: name what they did set
    throw ValueError(fmt::format(
        "Slurm: SLURM_ARRAY_TASK_ID={} and SLURM_ARRAY_TASK_COUNT={} (SLURM_ARRAY_TASK_MIN={}) "
        "do not name a task of the array (task ID - MIN must be below COUNT); check the "
        "job's --array, or pass --shard I/N explicitly.",
        id, count, min ? min : "unset"));
  }
}

RolloutSpec MakeSpec(const RolloutOptions& o, const Model& model, Notices* notices) {
  RolloutSpec spec;
  spec.sets = StartAssignments(model, o.keyframe, o.pose, o.sets);
  spec.count = o.count;
  spec.until = o.until;
  spec.threads = o.threads;
  spec.seed = o.seed;
  spec.ctrl_noise = o.ctrl_noise;
  if (o.shard.empty()) ShardFromSlurm(&spec);
  return ParseRolloutSpec(model, spec, {o.randomize, {}, o.metrics, o.shard}, notices);
}

// The batch in its results store: a new run, or the same run continued with --resume. Under
// MPI the other ranks wait for rank 0 to get this far (an error here must not leave them
// waiting).
BatchJob OpenRolloutJob(const RolloutOptions& o, const Context& ctx, const Model& model,
                        const RolloutSpec& spec, Notices& notices) {
  std::optional<BatchJob> job;
  try {
    BatchOrigin origin{o.model, ctx.argv,
                       StartConfig(model, {o.keyframe, o.pose.file, o.pose.qpos, o.sets})};
    job.emplace(o.db, o.resume, RolloutRunInfo(model, spec, origin, o.db), CliBatchWords(),
                &notices);
  } catch (...) {
    MpiGo(false);
    throw;
  }
  MpiGo(true);
  return std::move(*job);
}

// The rows as table, CSV or JSON, reaching stdout as they finish, in order (at most ten
// writes a second), so `plumb rollout ... | head -2` stops the batch early (exit 141, see
// WriteStdout).
class RolloutWriter {
 public:
  RolloutWriter(const std::string& format, const std::vector<std::string>& params,
                const std::vector<std::string>& metrics, ProgressBar& progress)
      : format_(format), json_(params, metrics), progress_(progress) {
    std::vector<std::string> columns = RolloutCsvColumns(params, metrics);
    if (format == "table") columns.resize(columns.size() - 2);  // problems go to stderr
    if (format == "csv") {
      out_ += CsvLine(columns);
    } else if (format == "json") {
      out_ += json_.Begin();
    } else {
      for (const std::string& c : columns) {
        widths_.push_back(std::max<int>(10, static_cast<int>(c.size()) + 2));
        out_ += fmt::format("{:>{}}", c, widths_.back());
      }
      out_ += "\n";
    }
    Flush();
  }

  void Row(const RolloutResult& r) {
    if (format_ == "csv") {
      out_ += RolloutCsvRow(r);
    } else if (format_ == "json") {
      out_ += json_.Row(r);
    } else {
      TableRow(r);
    }
    if (out_.size() > (1 << 16) ||
        std::chrono::steady_clock::now() - last_write_ > std::chrono::milliseconds(100)) {
      Flush();
    }
  }

  void Finish() {
    if (format_ == "json") out_ += json_.End();
    Flush();
  }

  void Flush() {
    last_write_ = std::chrono::steady_clock::now();
    if (out_.empty()) return;
    progress_.Clear();
    std::string text;
    text.swap(out_);
    WriteStdout(text);
  }

 private:
  void TableRow(const RolloutResult& r) {
    std::size_t w = 0;
    out_ += fmt::format("{:>{}}", r.index, widths_[w++]);
    for (double v : r.params) out_ += fmt::format("{:>{}.6g}", v, widths_[w++]);
    for (double v : r.metrics) {
      out_ += std::isnan(v) ? fmt::format("{:>{}}", "-", widths_[w++])
                            : fmt::format("{:>{}.6g}", v, widths_[w++]);
    }
    out_ += fmt::format("{:>{}}\n", r.diverged ? "yes" : "no", widths_[w++]);
    if (!r.problem.empty() && !r.diverged) {
      progress_.Clear();
      std::fprintf(stderr, "plumb: %s\n", r.problem.c_str());
    }
  }

  const std::string& format_;
  RolloutJson json_;
  ProgressBar& progress_;
  std::vector<int> widths_;
  std::string out_;
  std::chrono::steady_clock::time_point last_write_ = std::chrono::steady_clock::now();
};

// Runs the shard's rollouts not stored yet, `1 << 16` indices at a time (memory does not
// grow with --count), on MPI ranks or this process's worker pool.
void RunShard(const Model& model, const RolloutSpec& spec, long total, ProgressBar& progress,
              const std::function<void(const RolloutResult&)>& emit) {
  long next_index = spec.shard_index;
  auto next_indices = [&](std::size_t limit) {
    std::vector<long> chunk;
    for (; next_index < spec.count && chunk.size() < limit; next_index += spec.shard_count) {
      if (!std::binary_search(spec.skip.begin(), spec.skip.end(), next_index)) {
        chunk.push_back(next_index);
      }
    }
    return chunk;
  };
  if (MpiActive()) {
    // rank 0 hands the list out in small chunks; it holds the whole list (8 bytes each)
    MpiRollout(model, spec, next_indices(static_cast<std::size_t>(total)), emit,
               CommandStop().token());
    return;
  }
  RolloutSpec chunked = spec;
  long done_before = 0;
  chunked.progress = [&](long done, long) { progress.Update(done_before + done); };
  RolloutPool pool(model, chunked);  // worker models made once for all chunks
  for (std::vector<long> chunk = next_indices(1 << 16); !chunk.empty();
       chunk = next_indices(1 << 16)) {
    pool.Run(chunk, emit, CommandStop().token());
    done_before += static_cast<long>(chunk.size());
#ifdef __GLIBC__
    malloc_trim(0);  // hand freed pages back: resident memory stays flat as --count grows
#endif
  }
}

int RunRollout(const RolloutOptions& o, const Context& ctx) {
  internal::RefuseOutputsOntoInputs({{"--db", o.db}, {"--report", o.report}},
                                    ModelInputs(o.model, o.pose));
  Model model = LoadModel(o.model);
  BatchNotices notices;
  RolloutSpec spec = MakeSpec(o, model, MpiActive() && MpiRank() != 0 ? nullptr : &notices);
  std::vector<std::string> params = ParameterNames(spec);
  // under MPI, ranks other than 0 only compute what rank 0 hands them
  if (MpiActive() && MpiRank() != 0) {
    if (!MpiGo(true)) return kExitBadInput;  // rank 0 reports the error
    MpiRollout(model, spec, {}, nullptr, CommandStop().token());
    return kExitOk;
  }
  BatchJob job = OpenRolloutJob(o, ctx, model, spec, notices);
  spec.skip = job.done();
  // from here on an error on rank 0 stops every rank (see main)
  long total = ShardToRun(spec);  // counted, not listed: --count 2^53 starts at once
  ProgressBar progress(total, "rollouts");
  notices.Show(&progress);
  RolloutWriter writer(o.format, params, o.metrics, progress);
  std::optional<BatchCollector> batch;
  ReportInfo info{ctx.argv};
  if (!o.report.empty()) {
    batch.emplace(params, o.metrics);
    info.nominal_until = o.until;
    info.ahead = StartPictures(model, spec.sets, info);  // drawn while the rollouts run
  }
  // the summary: every row of the shard, stored before a --resume or run now
  RolloutEffects effects(spec, &model);  // a randomization that changed nothing gets a note
  job.Resume(ShardSize(spec), InShard(spec), [&](const RolloutResult& r) {
    effects.See(r);
    if (batch) batch->Add(r.params, r.metrics, r.diverged);
  });
  EtaNote eta("rollouts", job.stored(), progress);
  auto emit = [&](const RolloutResult& r) {
    job.Add(r);
    effects.See(r);
    eta.See(job.summary().run_now, total - job.summary().run_now);
    if (batch) batch->Add(r.params, r.metrics, r.diverged);
    writer.Row(r);
  };
  StopTimer budget(CommandStop(), o.max_seconds);  // --max-seconds
  KeepFinishedOnStop([&] { RunShard(model, spec, total, progress, emit); }, progress, job,
                     [&] { writer.Flush(); }, nullptr, budget);
  writer.Finish();
  progress.Finish();
  effects.Finish(&notices);
  job.Complete(spec.count);
  if (batch) {
    WriteBatchReport(o.report, "rollout", model, spec.sets, *batch, info);
    std::fprintf(stderr, "plumb: wrote the report %s\n", o.report.c_str());
  }
  // the human summary: after the table, or on stderr when stdout carries data
  std::string summary = job.summary().Text(o.metrics, job.unit(), job.seconds());
  if (o.format == "table") {
    WriteStdout(summary);
  } else {
    std::fwrite(summary.data(), 1, summary.size(), stderr);
  }
  return kExitOk;
}

}  // namespace

void SetupRolloutCommand(CLI::App& app, Context& ctx) {
  auto o = std::make_shared<RolloutOptions>();
  CLI::App* cmd = AddCommand(
      app, "rollout", "Many runs with randomized parameters, deterministic for any thread count",
      "Examples:\n"
      "  plumb rollout humanoid.xml --count 1000 --until 1 --threads 2 --seed 7 \\\n"
      "      --randomize 'body_mass[*]=*U(0.9,1.1)' --randomize 'geom_friction[*][0]=U(0.5,1.2)' "
      "\\\n"
      "      --ctrl-noise 0.01 --metric 'xpos[torso][2]@1' --format csv > rollouts.csv\n"
      "Distributions: U(a,b), N(mu,sigma), LogU(a,b); *DIST scales the nominal value, +DIST\n"
      "offsets it. Rows come out in rollout order with no timings: equal runs give equal output.\n"
      "With --format csv|json the summary goes to stderr. --shard I/N (or Slurm's\n"
      "SLURM_ARRAY_TASK_ID/SLURM_ARRAY_TASK_COUNT) runs the rollouts i with i % N == I.\n"
      "--db FILE records everything in SQLite; --resume skips what a killed run finished;\n"
      "plumb results FILE exports, plumb merge A B -o OUT joins shard files.");
  AddModelOptions(cmd, &o->model, &o->sets, "for every rollout");
  AddKeyframeOption(cmd, &o->keyframe);
  AddStartPoseOptions(cmd, &o->pose);
  cmd->add_option("--count", o->count, "number of rollouts (at least 1)")
      ->capture_default_str()
      ->check(CLI::Range(1L, 1L << 53));
  cmd->add_option("--until", o->until, "length of each rollout in s")->capture_default_str();
  cmd->add_option("--threads", o->threads, "worker threads")
      ->capture_default_str()
      ->check(CLI::Range(1, 1024));
  cmd->add_option("--seed", o->seed, "random seed")->capture_default_str();
  cmd->add_option("--randomize", o->randomize, "PATH=DIST (repeatable; '*' rows allowed)")
      ->allow_extra_args(false);
  cmd->add_option("--ctrl-noise", o->ctrl_noise,
                  "control noise as MuJoCo's testspeed: a fraction of each ctrlrange (0..1)")
      ->capture_default_str();
  cmd->add_option("--metric", o->metrics,
                  "PATH@T, maxabs(PATH), period(PATH), energy_drift or state@T (repeatable)")
      ->allow_extra_args(false);
  cmd->add_option("--shard", o->shard, "I/N: run the I-th of N disjoint slices");
  AddFormatOption(cmd, &o->format, {"table", "csv", "json"});
  cmd->add_option("--db", o->db, "record runs, cases and results in this SQLite file");
  cmd->add_option("--max-seconds", o->max_seconds,
                  "stop after this much wall time, keeping (printing and storing) the rollouts "
                  "that finished; exit 0 (with --db, --resume goes on)")
      ->check(CLI::PositiveNumber);
  cmd->add_flag("--resume", o->resume,
                "continue the same run in --db: skip rollouts already stored");
  AddReportOption(cmd, &o->report);
  cmd->callback([o, &ctx] { ctx.action = [o, &ctx] { return RunRollout(*o, ctx); }; });
}

}  // namespace plumb::cli
