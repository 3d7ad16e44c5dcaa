// The results store: an SQLite file (WAL mode) holding runs, their cases (sampled
// parameter values) and results (metrics, divergence), so batches can be resumed after
// a crash, exported, and merged across shards.
//
// Schema (stable; other tools may read it):
//   runs(id, kind, config, command, model_file, model_hash, plumb_version,
//        mujoco_version, started, finished, parameters, metrics, count)
//   cases(run, idx, params)            params: JSON array of numbers
//   results(run, idx, metrics, diverged, diverged_time, problem, warnings)
//                                      metrics: JSON array, null where unmeasured
//
// Example:
//   plumb::ResultsStore store("results.sqlite");
//   long run = store.BeginRun(info);             // or FindRun(config) to resume
//   store.Add(run, result); store.Commit();
//
// Crash safety: results are committed in batches (`batch`); a process killed at any moment
// loses at most the rows it had not committed, and the store opens and resumes afterwards.
// SQLite keeps committed rows in the write-ahead log, FILE-wal, until the next open folds
// them into FILE: never delete FILE-wal, FILE-shm or FILE-journal (a kill while a new store is
// made leaves a journal SQLite rolls back). Several processes may write one store at once
// (SQLite locks it; each waits up to 10 s for the other's commit).
//
// Thread-safety: use a ResultsStore from one thread at a time (its queue is not synchronised).
// Several stores, in one process or in several, may use one file at once: SQLite locks it.
// MergeStores opens stores of its own.

#ifndef PLUMB_INCLUDE_PLUMB_STORE_H_
#define PLUMB_INCLUDE_PLUMB_STORE_H_

#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "plumb/model.h"
#include "plumb/rollout.h"

namespace plumb {

struct RunInfo {
  long id = 0;
  std::string kind;     // "rollout"
  std::string config;   // canonical text of everything that decides the results
  std::string command;  // the command line (a merged run: one line per shard)
  std::string model_file;
  std::string model_hash;  // HashModel of the compiled model, hex
  std::string plumb_version, mujoco_version;
  std::string started, finished;  // ISO 8601 UTC; finished empty while incomplete
  std::vector<std::string> parameters, metrics;
  long count = 0;
};

// SQLite application_id of a plumb results store ("plmb").
inline constexpr int kStoreApplicationId = 0x706c6d62;
// The store's format, its SQLite user_version: 1 since the tables were made together (0 in
// stores from before, which have the same tables). A store of a later format, written by a
// newer plumb, is refused naming both formats, never half-read or altered.
inline constexpr int kStoreFormat = 1;

class ResultsStore {
 public:
  enum class Mode { kReadWrite, kReadOnly };

  // Opens the store; read-write creates it if needed (its tables all at once, so a process
  // killed meanwhile leaves a whole empty store or none) and runs SQLite's quick_check on an
  // existing one. Read-only writes nothing, except that a store whose writer was killed
  // mid-transaction first gets SQLite's own recovery (rolling back the journal), which only a
  // writable connection can make. @throws IoError naming the file when it cannot be opened,
  // is damaged, or is an SQLite file of some other program.
  explicit ResultsStore(const std::string& path, Mode mode = Mode::kReadWrite);
  ~ResultsStore();
  ResultsStore(const ResultsStore&) = delete;
  ResultsStore& operator=(const ResultsStore&) = delete;

  // The run with this exact config, if any. @throws IoError as Runs does.
  std::optional<RunInfo> FindRun(const std::string& config);
  // Records a new run and returns its id. @throws IoError.
  long BeginRun(const RunInfo& info);
  // Commits the queued results and marks `run` finished now. @throws IoError.
  void FinishRun(long run);
  // Runs `work` (which reads and writes through this store) in one write transaction, so
  // what it reads stays true until it commits, whatever other processes writing the store do
  // meanwhile: two processes that look for a run and begin it when it is missing begin one.
  // Queued results are committed first. Rolled back when `work` throws, which it rethrows.
  // @throws IoError when the store cannot be locked (another writer holds it over 10 s).
  void Transaction(const std::function<void()>& work);
  // Adds another command line to a run's record (a merged run keeps every shard's).
  // @throws IoError.
  void AppendCommand(long run, const std::string& command);
  // Every run, in id order. @throws IoError when SQLite fails or a row is damaged.
  std::vector<RunInfo> Runs();

  // Indices of the rollouts of `run` that already have results, sorted (queued results are
  // committed first). @throws IoError.
  std::vector<long> DoneIndices(long run);
  // How many there are, in constant memory (a million-rollout run checks it at its end).
  // @throws IoError.
  long CountDone(long run);

  // Queues one result (case and result rows); written at the next Commit, which also
  // happens automatically every `batch` rows. A process killed between commits loses
  // only the queued rows. @throws IoError as Commit does, when it commits.
  void Add(long run, const RolloutResult& result);
  // Writes the queued rows in one transaction; they stay queued when it fails.
  // @throws IoError when SQLite fails (e.g. another writer holds the store over 10 s).
  void Commit();

  // All results of a run in index order. @throws IoError as Runs does.
  std::vector<RolloutResult> Results(long run);
  // The same, one at a time, in memory that does not grow with the run. @throws IoError as
  // Runs does, and what `visit` throws.
  void ForEachResult(long run, const std::function<void(const RolloutResult&)>& visit);

  std::size_t batch = 64;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

// Copies every run of `inputs` into the store at `output` (which must not exist yet):
// runs with the same config become one run whose results are the union. @throws
// IoError, or ValueError when two inputs disagree on a result or the union has holes
// that the inputs claim are complete.
void MergeStores(const std::vector<std::string>& inputs, const std::string& output);

}  // namespace plumb

#endif  // PLUMB_INCLUDE_PLUMB_STORE_H_
