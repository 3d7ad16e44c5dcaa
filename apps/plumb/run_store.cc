#include "run_store.h"

#include <fmt/format.h>

#include <algorithm>
#include <cstdio>

#include "plumb/error.h"
#include "plumb/strings.h"
#include "plumb/version.h"

namespace plumb::cli {

RunInfo NewRunInfo(const std::string& kind, const std::string& config, const Context& ctx,
                   const std::string& model_file, const std::string& model_hash) {
  RunInfo info;
  info.kind = kind;
  info.config = config;
  std::vector<std::string> quoted;
  for (const std::string& a : ctx.argv) quoted.push_back(ShellQuote(a));
  info.command = fmt::format("{}", fmt::join(quoted, " "));
  info.model_file = model_file;
  info.model_hash = model_hash;
  info.plumb_version = PLUMB_VERSION;
  info.mujoco_version = MujocoVersion();
  return info;
}

StoredRun OpenStoredRun(const std::string& db, bool resume, const RunInfo& info) {
  StoredRun out;
  if (db.empty()) {
    if (resume) throw ValueError("--resume needs --db FILE");
    return out;
  }
  out.store = std::make_unique<ResultsStore>(db);
  ResultsStore& store = *out.store;
  // one transaction from looking for the run to beginning it: two processes started at once
  // begin one run, which the second joins with --resume or is refused without
  store.Transaction([&] {
    std::optional<RunInfo> existing = store.FindRun(info.config);
    if (existing && !resume) {
      throw ValueError(fmt::format(
          "results store '{}' already holds this run ({} run {}, {} of {} done); add --resume to "
          "complete it, or use another --db file.",
          db, info.kind, existing->id, store.CountDone(existing->id), existing->count));
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
        // a resume of a run this command does not describe: say what differs
        std::vector<std::string> mine = Split(info.config, ' '), theirs = Split(last->config, ' ');
        std::vector<std::string> differences;
        for (const std::string& t : theirs) {
          if (std::find(mine.begin(), mine.end(), t) == mine.end()) {
            differences.push_back("stored " + t);
          }
        }
        for (const std::string& t : mine) {
          if (std::find(theirs.begin(), theirs.end(), t) == theirs.end()) {
            differences.push_back("now " + t);
          }
        }
        throw ValueError(fmt::format(
            "--resume: this command is not the {} run stored in '{}' (run {}), so its results "
            "would not be comparable: {}. Repeat the stored command ({}) or use a new --db file.",
            info.kind, db, last->id, fmt::join(differences, ", "), last->command));
      }
      // nothing to resume: the first attempt of a job that is always started with --resume
      std::fprintf(stderr, "plumb: --resume: '%s' holds no %s run yet; starting one\n", db.c_str(),
                   info.kind.c_str());
    }
    out.id = store.BeginRun(info);
  });
  return out;
}

void KeepFinishedOnStop(const std::function<void()>& work, ProgressBar& progress, StoredRun& stored,
                        const std::function<void()>& flush,
                        const std::function<std::string()>& finished, const std::string& db,
                        WallClockBudget& budget) {
  try {
    work();
    budget.Finish();
    if (budget.Spent()) CommandStop().Clear();  // spent as the last case finished: nothing to stop
  } catch (const Interrupted& e) {
    // Ctrl-C or SIGTERM: what finished is printed and stored, so --resume loses nothing
    progress.Finish();
    if (stored.store) stored.store->Commit();
    try {
      flush();
    } catch (const OutputClosed&) {
    }
    budget.Finish();
    if (budget.Spent()) {
      CommandStop().Clear();  // the budget's stop, not a signal's: the command ends normally
      std::fprintf(stderr, "plumb: --max-seconds %g spent: %s%s\n", budget.seconds(),
                   finished().c_str(),
                   stored.store ? (" and stored in '" + db + "': --resume goes on").c_str() : "");
      return;
    }
    throw Interrupted(fmt::format(
        "{}; {}{}", e.what(), finished(),
        stored.store ? " and stored in '" + db + "': repeat the command with --resume to go on"
                     : ""));
  } catch (const OutputClosed&) {
    // the reader has gone: keep what finished, stop quietly
    progress.Finish();
    if (stored.store) stored.store->Commit();
    throw;
  }
}

void CompleteStoredRun(StoredRun& stored, long total) {
  if (!stored.store) return;
  stored.store->Commit();
  if (stored.store->CountDone(stored.id) == total) {
    stored.store->FinishRun(stored.id);
  }
}

}  // namespace plumb::cli
