// A batch's place in a results store (plumb/store.h): the protocol of resumable batches.
//
// A batch (a rollout, a sweep) describes itself by its config, the canonical text of
// everything that decides its results. Opening it in a store finds that run or begins it:
//   - the run exists: resuming continues it (`done` lists what it already holds); without
//     resuming it is refused, so a finished batch is never silently run twice;
//   - no such run: it is begun. When resuming, that is a fresh start if the store holds no run
//     of this kind (a preemptible job's first attempt, started the way every later attempt
//     is); if it holds another run of this kind, the refusal names every part of the config
//     that differs and the stored command.
//
// Example:
//   plumb::StoredRun run = plumb::OpenStoredRun("r.sqlite", /*resume=*/true,
//                                               plumb::NewRunInfo("rollout", config, argv,
//                                                                 "arm.xml", hash));
//   ... store rows for the indices not in run.done ...
//   plumb::CompleteStoredRun(run, count);
//
// Thread-safety: as ResultsStore: one StoredRun per thread. Opening is one transaction, so
// processes that start the same batch at once begin one run.

#ifndef PLUMB_INCLUDE_PLUMB_STORED_RUN_H_
#define PLUMB_INCLUDE_PLUMB_STORED_RUN_H_

#include <memory>
#include <string>
#include <vector>

#include "plumb/error.h"
#include "plumb/model.h"
#include "plumb/store.h"

namespace plumb {

struct StoredRun {
  std::unique_ptr<ResultsStore> store;  // empty when the batch is not stored
  long id = 0;
  std::vector<long> done;  // indices already stored (sorted): what a resumed batch skips
  // Resuming found no run of this kind and began one (the first attempt of a resumable job).
  bool fresh_start = false;
};

// The store holds this batch already, and it was not resumed (argument "store"): run() is the
// stored run, done() how many of its indices it holds.
class RunAlreadyStored : public ArgumentError {
 public:
  RunAlreadyStored(const std::string& path, RunInfo run, long done);
  const RunInfo& run() const { return run_; }
  long done() const { return done_; }

 private:
  RunInfo run_;
  long done_;
};

// The record of a new run: `kind` and `config` as given, `command` (the words of the command
// line, quoted so the line can be pasted), the model file and hash, and the versions of plumb
// and MuJoCo.
RunInfo NewRunInfo(const std::string& kind, const std::string& config,
                   const std::vector<std::string>& command, const std::string& model_file,
                   const std::string& model_hash);

// The part of a batch's config that says what its runs start from beyond qpos, qvel, act and
// ctrl: " start_state=mjSTATE_INTEGRATION" when `model` has delay history or plastic state
// (MuJoCo 3.5+ and 4.0), which runs start from as MuJoCo's reset and keyframes set them;
// empty otherwise. Runs stored before plumb restored that state lack it, so resuming one of
// them is refused with this difference named instead of mixing rows of two starts.
std::string StartStateConfig(const Model& model);

// Opens the store at `path` (nothing when it is empty) and finds the run `info.config`
// describes or begins it, as the header says.
// @throws ArgumentError "resume" when resuming without a store; RunAlreadyStored when the
// store holds this run and `resume` is false; ArgumentError "store" (the path) when resuming
// and it holds another run of this kind; IoError from the store.
StoredRun OpenStoredRun(const std::string& path, bool resume, const RunInfo& info);

// Commits the store and marks the run finished when it holds all `total` indices.
void CompleteStoredRun(StoredRun& stored, long total);

// What a batch that a stop request ended says, the same from every front end: `stopped` (the
// batch's Interrupted: "interrupted after 12 rollouts"), `finished` ("12 rollouts
// finished") and, when it is stored in `path` (empty when not), that every finished one is
// stored there and how to go on, in the front end's words (`resume`: "repeat the command
// with ..." or "call it again with resume=True"). Example: "interrupted after 12 rollouts;
// 12 rollouts finished and stored in 'r.sqlite': call it again with resume=True to go on".
std::string StoppedBatchMessage(const std::string& stopped, const std::string& finished,
                                const std::string& path, const std::string& resume);

}  // namespace plumb

#endif  // PLUMB_INCLUDE_PLUMB_STORED_RUN_H_
