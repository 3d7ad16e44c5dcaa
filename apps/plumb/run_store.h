// The --db/--resume flags of plumb's batch commands (rollout, sweep) over the library's
// protocol (plumb/stored_run.h), and keeping what finished when a batch stops early.

#ifndef PLUMB_APPS_PLUMB_RUN_STORE_H_
#define PLUMB_APPS_PLUMB_RUN_STORE_H_

#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "budget.h"
#include "cli_common.h"
#include "plumb/stored_run.h"

namespace plumb::cli {

// Opens the batch's store (plumb::OpenStoredRun) and says on stderr when resuming began a
// new run. The errors name --db and --resume.
StoredRun OpenBatchStore(const std::string& db, bool resume, const RunInfo& info);

// Runs a batch's `work`, keeping what finished when it stops early. On a stop request
// (Interrupted) the progress line is closed, the store committed, the rows not yet printed
// written (unless stdout is gone), and the stop is reported again with `finished` ("12
// rollouts finished") and, with a store, how to go on (--resume). On a closed stdout
// (OutputClosed) the store is committed and the batch ends quietly (exit 141). When `budget`
// stopped it (--max-seconds), the same is kept and said, and KeepFinishedOnStop returns: the
// command goes on to its summary and exits 0.
void KeepFinishedOnStop(const std::function<void()>& work, ProgressBar& progress, StoredRun& stored,
                        const std::function<void()>& flush,
                        const std::function<std::string()>& finished, const std::string& db,
                        StopTimer& budget);

}  // namespace plumb::cli

#endif  // PLUMB_APPS_PLUMB_RUN_STORE_H_
