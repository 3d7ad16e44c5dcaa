// plumb rollout: many runs with domain randomization, deterministic for any threads.

#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <nlohmann/json.hpp>
#include <optional>

#ifdef __GLIBC__
#include <malloc.h>
#endif

#include "cli_common.h"
#include "plumb/strings.h"
#include "plumb/version.h"
#include "mpi.h"
#include "plumb/error.h"
#include "plumb/output.h"
#include "plumb/rollout.h"
#include "plumb/hash.h"
#include "plumb/store.h"
#include "run_store.h"
#include "summary.h"

namespace plumb::cli {
namespace {

struct RolloutOptions {
  std::string model;
  std::vector<std::string> sets;
  std::string keyframe;
  long count = 100;
  double until = 2;
  int threads = 1;
  std::uint64_t seed = 0;
  std::vector<std::string> randomize;
  double ctrl_noise = 0;
  std::vector<std::string> metrics;
  std::string format = "table";
  std::string shard;
  std::string db;
  bool resume = false;
};

// Everything that decides a rollout batch's results, as one canonical line: the same
// config means the same rows, so --resume may continue it and merge may join shards.
// The model enters as the hash of its compiled form (included files count), and the
// versions of plumb and MuJoCo, which decide the numbers as much as the options do.
std::string Config(const RolloutOptions& o, const std::string& model_hash) {
  std::string config = fmt::format(
      "rollout model={} count={} until={:.17g} seed={} "
      "ctrl_noise={:.17g} plumb={} mujoco={}",
      model_hash, o.count, o.until, o.seed, o.ctrl_noise, PLUMB_VERSION, MujocoVersion());
  if (!o.keyframe.empty()) config += " keyframe=" + o.keyframe;
  for (const std::string& s : o.sets) config += " set=" + s;
  for (const std::string& r : o.randomize) config += " randomize=" + r;
  for (const std::string& m : o.metrics) config += " metric=" + m;
  return config;
}

// "I/N", or the Slurm job array's task id and count when --shard is absent.
void ParseShard(const std::string& text, RolloutSpec* spec) {
  std::string shard = text;
  if (shard.empty()) {
    // array ids run from SLURM_ARRAY_TASK_MIN (often 1, as in --array=1-8), not from 0
    const char* id = std::getenv("SLURM_ARRAY_TASK_ID");
    const char* count = std::getenv("SLURM_ARRAY_TASK_COUNT");
    const char* min = std::getenv("SLURM_ARRAY_TASK_MIN");
    if (!id || !count) return;
    std::optional<long> i = ParseIndex(id), lowest = ParseIndex(min ? min : "0");
    if (!i || !lowest || *i < *lowest) {
      throw ValueError(fmt::format(
          "Slurm: SLURM_ARRAY_TASK_ID={} with SLURM_ARRAY_TASK_MIN={} is not a task of the "
          "array; pass --shard I/N explicitly.",
          id, min ? min : "(unset)"));
    }
    shard = std::to_string(*i - *lowest) + "/" + count;
  }
  std::vector<std::string> parts = Split(shard, '/');
  std::optional<long> i = parts.size() == 2 ? ParseIndex(parts[0]) : std::nullopt;
  std::optional<long> n = parts.size() == 2 ? ParseIndex(parts[1]) : std::nullopt;
  if (!i || !n || *n < 1 || *i >= *n) {
    if (text.empty()) {
      // the user passed no --shard: name what they did set
      const char* min = std::getenv("SLURM_ARRAY_TASK_MIN");
      throw ValueError(fmt::format(
          "Slurm: SLURM_ARRAY_TASK_ID={} and SLURM_ARRAY_TASK_COUNT={} (SLURM_ARRAY_TASK_MIN={}) "
          "do not name a task of the array (task ID - MIN must be below COUNT); check the "
          "job's --array, or pass --shard I/N explicitly.",
          std::getenv("SLURM_ARRAY_TASK_ID"), std::getenv("SLURM_ARRAY_TASK_COUNT"),
          min ? min : "unset"));
    }
    throw ValueError("--shard '" + shard + "': expected I/N with 0 <= I < N, e.g. 0/4.");
  }
  spec->shard_index = *i;
  spec->shard_count = *n;
}

int RunRollout(const RolloutOptions& o, const Context& ctx) {
  Model model = LoadModel(o.model);
  RolloutSpec spec;
  spec.sets = StartAssignments(model, o.keyframe, o.sets);
  for (const std::string& r : o.randomize) spec.randomize.push_back(ParseRandomization(model, r));
  for (const std::string& m : o.metrics) spec.metrics.push_back(ParseMetric(model, m));
  spec.count = o.count;
  spec.until = o.until;
  spec.threads = o.threads;
  spec.seed = o.seed;
  spec.ctrl_noise = o.ctrl_noise;
  ParseShard(o.shard, &spec);
  std::vector<std::string> params = ParameterNames(spec);

  // the results store: a new run, or the same run continued with --resume
  if (o.resume && o.db.empty()) throw ValueError("--resume needs --db FILE");
  ValidateRolloutSpec(model, spec);
  // under MPI, ranks other than 0 only compute what rank 0 hands them, once rank 0 has
  // set up the store (an error there must not leave them waiting)
  if (MpiActive() && MpiRank() != 0) {
    if (!MpiGo(true)) return kExitBadInput;  // rank 0 reports the error
    MpiRollout(model, spec, {}, nullptr);
    return kExitOk;
  }
  StoredRun stored;
  try {
    // the compiled model's hash names the run in the store; hashing a big mesh model costs
    // a tenth of a second, so only when there is a store
    std::string model_hash = o.db.empty() ? std::string() : HashModel(model);
    RunInfo info = NewRunInfo("rollout", Config(o, model_hash), ctx, o.model, model_hash);
    info.parameters = params;
    info.metrics = o.metrics;
    info.count = o.count;
    stored = OpenStoredRun(o.db, o.resume, info);
    spec.skip = stored.done;
  } catch (...) {
    MpiGo(false);
    throw;
  }
  MpiGo(true);
  std::unique_ptr<ResultsStore>& store = stored.store;
  const long run_id = stored.id;
  // from here on an error on rank 0 stops every rank (see main)

  long total = 0;
  for (long i = spec.shard_index; i < spec.count; i += spec.shard_count) {
    if (!std::binary_search(spec.skip.begin(), spec.skip.end(), i)) ++total;
  }
  ProgressBar progress(total, "rollouts");
  spec.progress = [&](long done, long) { progress.Update(done); };

  // header
  std::vector<std::string> columns = RolloutCsvColumns(params, o.metrics);
  if (o.format == "table") columns.resize(columns.size() - 2);  // problems go to stderr
  // rows reach stdout as they finish, in order (at most ten writes a second), so
  // `plumb rollout ... | head -2` stops the batch early (exit 141, see WriteStdout)
  std::string out;
  auto last_write = std::chrono::steady_clock::now();
  auto flush = [&] {
    last_write = std::chrono::steady_clock::now();
    if (out.empty()) return;
    progress.Clear();
    std::string text;
    text.swap(out);
    WriteStdout(text);
  };
  std::vector<int> widths;
  if (o.format == "csv") {
    out += CsvHeader(columns);
  } else if (o.format == "json") {
    out += "[\n";
  } else {
    for (const std::string& c : columns) {
      widths.push_back(std::max<int>(10, static_cast<int>(c.size()) + 2));
      out += fmt::format("{:>{}}", c, widths.back());
    }
    out += "\n";
  }
  flush();

  // a resumed run's summary covers every row of its shard, stored before or run now
  std::vector<Summary> summaries(spec.metrics.size());
  long diverged = 0, emitted = 0, resumed = 0;
  if (store && !spec.skip.empty()) {
    store->ForEachResult(run_id, [&](const RolloutResult& r) {
      if (r.index % spec.shard_count != spec.shard_index) return;
      ++resumed;
      diverged += r.diverged;
      for (std::size_t k = 0; k < r.metrics.size() && k < summaries.size(); ++k) {
        summaries[k].Add(r.metrics[k]);
      }
    });
  }
  auto start = std::chrono::steady_clock::now();
  // the indices of this shard that are not stored yet, `limit` at a time: memory does
  // not grow with --count
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
  auto run = [&](const std::function<void(const RolloutResult&)>& emit) {
    if (MpiActive()) {
      // rank 0 hands the list out in small chunks; it holds the whole list (8 bytes each)
      MpiRollout(model, spec, next_indices(static_cast<std::size_t>(total)), emit);
      return;
    }
    RolloutSpec chunked = spec;
    long done_before = 0;
    chunked.progress = [&](long done, long) { progress.Update(done_before + done); };
    RolloutPool pool(model, chunked);  // worker models made once for all chunks
    for (std::vector<long> chunk = next_indices(1 << 16); !chunk.empty();
         chunk = next_indices(1 << 16)) {
      pool.Run(chunk, emit, &StopRequested());
      done_before += static_cast<long>(chunk.size());
#ifdef __GLIBC__
      malloc_trim(0);  // hand freed pages back: resident memory stays flat as --count grows
#endif
    }
  };
  auto emit = [&](const RolloutResult& r) {
    ++emitted;
    diverged += r.diverged;
    if (store) store->Add(run_id, r);
    for (std::size_t k = 0; k < r.metrics.size(); ++k) summaries[k].Add(r.metrics[k]);
    if (o.format == "csv") {
      out += RolloutCsvRow(r);
    } else if (o.format == "json") {
      nlohmann::ordered_json row;
      row["rollout"] = r.index;
      nlohmann::ordered_json p = nlohmann::ordered_json::object(), m = p;
      for (std::size_t k = 0; k < r.params.size(); ++k) p[params[k]] = r.params[k];
      for (std::size_t k = 0; k < r.metrics.size(); ++k) {
        m[o.metrics[k]] = std::isnan(r.metrics[k]) ? nlohmann::ordered_json(nullptr)
                                                   : nlohmann::ordered_json(r.metrics[k]);
      }
      row["params"] = p;
      row["metrics"] = m;
      row["diverged"] = r.diverged;
      if (r.diverged) row["diverged_time"] = r.diverged_time;
      if (!r.problem.empty()) row["problem"] = r.problem;
      out += (emitted > 1 ? ",\n  " : "  ") + row.dump();
    } else {
      std::size_t w = 0;
      out += fmt::format("{:>{}}", r.index, widths[w++]);
      for (double v : r.params) out += fmt::format("{:>{}.6g}", v, widths[w++]);
      for (double v : r.metrics) {
        out += std::isnan(v) ? fmt::format("{:>{}}", "-", widths[w++])
                             : fmt::format("{:>{}.6g}", v, widths[w++]);
      }
      out += fmt::format("{:>{}}\n", r.diverged ? "yes" : "no", widths[w++]);
      if (!r.problem.empty() && !r.diverged) {
        progress.Clear();
        std::fprintf(stderr, "plumb: %s\n", r.problem.c_str());
      }
    }
    if (out.size() > (1 << 16) ||
        std::chrono::steady_clock::now() - last_write > std::chrono::milliseconds(100)) {
      flush();
    }
  };
  try {
    run(emit);
  } catch (const Interrupted& e) {
    // Ctrl-C or SIGTERM: what finished is printed and stored, so --resume loses nothing
    progress.Finish();
    if (store) store->Commit();
    try {
      flush();
    } catch (const OutputClosed&) {
    }
    throw Interrupted(fmt::format("{}; {} rollouts finished{}", e.what(), emitted,
                                  store ? " and are stored in '" + o.db +
                                              "': repeat the command with --resume to go on"
                                        : ""));
  } catch (const OutputClosed&) {
    // the reader has gone: keep what finished, stop quietly
    progress.Finish();
    if (store) store->Commit();
    throw;
  }
  if (o.format == "json") out += "\n]\n";
  flush();
  progress.Finish();
  if (store) {
    store->Commit();
    if (static_cast<long>(store->DoneIndices(run_id).size()) == spec.count)
      store->FinishRun(run_id);
  }
  double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();

  // the human summary: after the table, or on stderr when stdout carries data
  long all = emitted + resumed;
  std::string summary = fmt::format(
      "\n{} rollouts{}, {} diverged ({:.1f}%), {:.1f} rollouts/s\n", all,
      resumed ? fmt::format(" ({} stored before this --resume, {} run now)", resumed, emitted)
              : "",
      diverged, all ? 100.0 * diverged / all : 0.0, seconds > 0 ? emitted / seconds : 0.0);
  for (std::size_t k = 0; k < summaries.size(); ++k) {
    const Summary& s = summaries[k];
    if (s.count() == 0) {
      // no value to summarise: no mean, and no +-inf from empty minima and maxima
      summary +=
          fmt::format("{}: n 0, no value measured ({} missing)\n", o.metrics[k], s.missing());
      continue;
    }
    summary += fmt::format(
        "{}: n {} mean {:.6g} std {:.6g} min {:.6g} q05 {:.6g} median {:.6g} q95 {:.6g} max "
        "{:.6g}{}\n",
        o.metrics[k], s.count(), s.mean(), s.stddev(), s.min(), s.q05(), s.q50(), s.q95(), s.max(),
        s.missing() ? fmt::format(" ({} not measured)", s.missing()) : "");
  }
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
  CLI::App* cmd = app.add_subcommand(
      "rollout", "Many runs with randomized parameters, deterministic for any thread count");
  cmd->footer(
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
  cmd->add_flag("--resume", o->resume,
                "continue the same run in --db: skip rollouts already stored");
  cmd->callback([o, &ctx] { ctx.action = [o, &ctx] { return RunRollout(*o, ctx); }; });
}

}  // namespace plumb::cli
