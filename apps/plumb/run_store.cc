#include "run_store.h"

#include <cstdio>

#include "plumb/error.h"

namespace plumb::cli {

BatchWords CliBatchWords() {
  return {"--db", "--resume", "repeat the command with --resume", "--vary"};  // command
}

BatchNotices::BatchNotices()
    : Notices([this](const Notice& notice) {
        if (progress_) progress_->Clear();
        PrintNotice(notice);
      }) {}

void KeepFinishedOnStop(const std::function<void()>& work, ProgressBar& progress, BatchJob& job,
                        const std::function<void()>& flush,
                        const std::function<std::string()>& finished, StopTimer& budget) {
  auto said = [&] { return finished ? finished() : job.Finished(); };
  try {
    job.Run(work, finished);
    budget.Finish();
    if (budget.Spent()) CommandStop().Clear();  // spent as the last case finished: nothing to stop
  } catch (const Interrupted&) {
    // Ctrl-C or SIGTERM: what finished is printed and stored (job.Run committed it), so
    // --resume loses nothing
    progress.Finish();
    try {
      flush();
    } catch (const OutputClosed&) {
    }
    budget.Finish();
    if (budget.Spent()) {
      CommandStop().Clear();  // the budget's stop, not a signal's: the command ends normally
      std::fprintf(stderr, "plumb: --max-seconds %g spent: %s%s\n", budget.seconds(),
                   said().c_str(),
                   job.stored() ? (" and stored in '" + job.db() + "': --resume goes on").c_str()
                                : "");
      return;
    }
    throw;
  } catch (const OutputClosed&) {
    // the reader has gone: keep what finished, stop quietly
    progress.Finish();
    job.Commit();
    throw;
  }
}

}  // namespace plumb::cli
