#include "run_store.h"

#include <fmt/format.h>

#include <cstdio>

#include "plumb/error.h"

namespace plumb::cli {

StoredRun OpenBatchStore(const std::string& db, bool resume, const RunInfo& info) {
  StoredRun stored;
  try {
    stored = OpenStoredRun(db, resume, info);
  } catch (const RunAlreadyStored& e) {
    throw ValueError(fmt::format(
        "results store '{}' already holds this run ({} run {}, {} of {} done); add --resume to "
        "complete it, or use another --db file.",
        db, e.run().kind, e.run().id, e.done(), e.run().count));
  }
  if (stored.fresh_start) {
    std::fprintf(stderr, "plumb: --resume: '%s' holds no %s run yet; starting one\n", db.c_str(),
                 info.kind.c_str());
  }
  return stored;
}

void KeepFinishedOnStop(const std::function<void()>& work, ProgressBar& progress, StoredRun& stored,
                        const std::function<void()>& flush,
                        const std::function<std::string()>& finished, const std::string& db,
                        StopTimer& budget) {
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
    throw Interrupted(StoppedBatchMessage(e.what(), finished(), stored.store ? db : "",
                                          "repeat the command with --resume"));
  } catch (const OutputClosed&) {
    // the reader has gone: keep what finished, stop quietly
    progress.Finish();
    if (stored.store) stored.store->Commit();
    throw;
  }
}

}  // namespace plumb::cli
