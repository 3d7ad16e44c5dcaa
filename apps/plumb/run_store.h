// The --db/--resume protocol of plumb's batch commands (rollout, sweep): find or begin the
// run in the results store, refuse a resume that is not the same run, and read back what a
// resumed run already holds.

#ifndef PLUMB_APPS_PLUMB_RUN_STORE_H_
#define PLUMB_APPS_PLUMB_RUN_STORE_H_

#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "budget.h"
#include "cli_common.h"
#include "plumb/store.h"

namespace plumb::cli {

// A batch run's place in its results store.
struct StoredRun {
  std::unique_ptr<ResultsStore> store;  // empty without --db
  long id = 0;
  std::vector<long> done;  // indices already stored (sorted): what --resume skips
};

// The record of a new run: `kind` and `config` as given, the command line quoted so it
// can be pasted, the model file and the versions of plumb and MuJoCo.
RunInfo NewRunInfo(const std::string& kind, const std::string& config, const Context& ctx,
                   const std::string& model_file, const std::string& model_hash);

// Opens `db` (nothing when empty) and finds the run `info.config` describes or begins it.
// - the run exists: --resume continues it (`done` lists what it holds); without --resume it
//   is refused, so a finished batch is never silently run twice;
// - no such run: it is begun. With --resume that is a fresh start when the store holds no
//   run of this kind (a preemptible job's first attempt); when it holds another run of this
//   kind, the refusal names every option that differs and the stored command.
// @throws ValueError; IoError from the store.
StoredRun OpenStoredRun(const std::string& db, bool resume, const RunInfo& info);

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
                        WallClockBudget& budget);

// Commits the store and marks the run finished when it holds all `total` indices.
void CompleteStoredRun(StoredRun& stored, long total);

}  // namespace plumb::cli

#endif  // PLUMB_APPS_PLUMB_RUN_STORE_H_
