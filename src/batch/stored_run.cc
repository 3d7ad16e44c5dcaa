// The protocol of resumable batches (include/plumb/stored_run.h).

#include "plumb/stored_run.h"

#include <fmt/format.h>

#include <algorithm>

#include "core/mujoco_compat.h"
#include "core/strings.h"
#include "plumb/error.h"
#include "plumb/model.h"
#include "plumb/version.h"

namespace plumb {
namespace {

// The parts of two configs that differ: "stored X" for what only the stored run has, "now Y"
// for what only this one has.
std::vector<std::string> ConfigDifferences(const std::string& now, const std::string& stored) {
  std::vector<std::string> mine = internal::Split(now, ' '), theirs = internal::Split(stored, ' ');
  std::vector<std::string> differences;
  for (const std::string& t : theirs) {
    if (std::find(mine.begin(), mine.end(), t) == mine.end()) differences.push_back("stored " + t);
  }
  for (const std::string& t : mine) {
    if (std::find(theirs.begin(), theirs.end(), t) == theirs.end()) {
      differences.push_back("now " + t);
    }
  }
  return differences;
}

}  // namespace

RunAlreadyStored::RunAlreadyStored(const std::string& path, RunInfo run, long done)
    : ArgumentError("store", Quoted(path),
                    fmt::format("the results store already holds this run ({} run {}, {} of {} "
                                "done); resume it to complete it, or use another store file.",
                                run.kind, run.id, done, run.count)),
      run_(std::move(run)),
      done_(done) {}

std::string StartStateConfig(const Model& model) {
  bool more = compat::HistorySize(model.get()) > 0 || compat::PlasticSize(model.get()) > 0;
  return more ? " start_state=" + std::string(compat::kIntegrationStateName) : "";
}

RunInfo NewRunInfo(const std::string& kind, const std::string& config,
                   const std::vector<std::string>& command, const std::string& model_file,
                   const std::string& model_hash) {
  RunInfo info;
  info.kind = kind;
  info.config = config;
  std::vector<std::string> quoted;
  for (const std::string& a : command) quoted.push_back(internal::ShellQuote(a));
  info.command = internal::Join(quoted, " ");
  info.model_file = model_file;
  info.model_hash = model_hash;
  info.plumb_version = PLUMB_VERSION;
  info.mujoco_version = MujocoVersion();
  return info;
}

StoredRun OpenStoredRun(const std::string& path, bool resume, const RunInfo& info) {
  StoredRun out;
  if (path.empty()) {
    if (resume) throw ArgumentError("resume", "", "resuming needs a results store file");
    return out;
  }
  out.store = std::make_unique<ResultsStore>(path);
  ResultsStore& store = *out.store;
  // one transaction from looking for the run to beginning it: two processes started at once
  // begin one run, which the second joins by resuming or is refused without
  store.Transaction([&] {
    std::optional<RunInfo> existing = store.FindRun(info.config);
    if (existing && !resume) {
      throw RunAlreadyStored(path, *existing, store.CountDone(existing->id));
    }
    if (existing) {
      out.id = existing->id;
      out.done = store.DoneIndices(out.id);
      return;
    }
    if (resume) {
      std::optional<RunInfo> last;
      for (RunInfo& run : store.Runs()) {
        if (run.kind == info.kind) last = run;
      }
      if (last) {
        // a resume of a run this batch does not describe: say what differs
        throw ArgumentError(
            "store", Quoted(path),
            fmt::format("this batch is not the {} run stored there (run {}), so its results "
                        "would not be comparable: {}. Repeat the stored command ({}) or use a "
                        "new store file.",
                        info.kind, last->id,
                        internal::Join(ConfigDifferences(info.config, last->config), ", "),
                        last->command));
      }
      out.fresh_start = true;  // nothing to resume: a resumable job's first attempt
    }
    out.id = store.BeginRun(info);
  });
  return out;
}

void CompleteStoredRun(StoredRun& stored, long total) {
  if (!stored.store) return;
  stored.store->Commit();
  if (stored.store->CountDone(stored.id) == total) stored.store->FinishRun(stored.id);
}

std::string StoppedBatchMessage(const std::string& stopped, const std::string& finished,
                                const std::string& path, const std::string& resume) {
  if (path.empty()) return fmt::format("{}; {}", stopped, finished);
  return fmt::format("{}; {} and stored in {}: {} to go on", stopped, finished, Quoted(path),
                     resume);
}

}  // namespace plumb
