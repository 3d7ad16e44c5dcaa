// The --db/--resume flags of plumb's batch commands (rollout, sweep) over the library's batch
// job (plumb/batch_job.h), and keeping what finished when a batch stops early.

#ifndef PLUMB_APPS_PLUMB_RUN_STORE_H_
#define PLUMB_APPS_PLUMB_RUN_STORE_H_

#include <functional>
#include <string>

#include "budget.h"
#include "cli_common.h"
#include "plumb/batch_job.h"
#include "plumb/notice.h"

namespace plumb::cli {

// How the batch commands' messages name their flags (--db, --resume, --vary).
BatchWords CliBatchWords();

// A batch command's notices: each printed as it comes (PrintNotice), after clearing the
// progress bar once there is one (Show).
class BatchNotices : public Notices {
 public:
  BatchNotices();
  void Show(ProgressBar* progress) { progress_ = progress; }

 private:
  ProgressBar* progress_ = nullptr;
};

// Runs a batch's `work` in `job`, keeping what finished when it stops early. On a stop request
// (Interrupted) the store is committed, the progress line closed, the rows not yet printed
// written (unless stdout is gone), and the stop is reported again as the job says it, with
// `finished` ("12 rollouts finished"; empty: the job's count) and how to go on (--resume). On a
// closed stdout (OutputClosed) the store is committed and the batch ends quietly (exit 141).
// When `budget` stopped it (--max-seconds), the same is kept and said, and KeepFinishedOnStop
// returns: the command goes on to its summary and exits 0.
void KeepFinishedOnStop(const std::function<void()>& work, ProgressBar& progress, BatchJob& job,
                        const std::function<void()>& flush,
                        const std::function<std::string()>& finished, StopTimer& budget);

}  // namespace plumb::cli

#endif  // PLUMB_APPS_PLUMB_RUN_STORE_H_
