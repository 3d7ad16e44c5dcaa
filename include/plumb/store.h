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

class ResultsStore {
 public:
  enum class Mode { kReadWrite, kReadOnly };

  // Opens the store; read-write creates it if needed and runs SQLite's quick_check on an
  // existing one, read-only never writes. @throws IoError naming the file when it cannot
  // be opened, is damaged, or is an SQLite file of some other program.
  explicit ResultsStore(const std::string& path, Mode mode = Mode::kReadWrite);
  ~ResultsStore();
  ResultsStore(const ResultsStore&) = delete;
  ResultsStore& operator=(const ResultsStore&) = delete;

  // The run with this exact config, if any.
  std::optional<RunInfo> FindRun(const std::string& config);
  // Records a new run and returns its id.
  long BeginRun(const RunInfo& info);
  void FinishRun(long run);
  // Adds another command line to a run's record (a merged run keeps every shard's).
  void AppendCommand(long run, const std::string& command);
  std::vector<RunInfo> Runs();

  // Indices of the rollouts of `run` that already have results, sorted.
  std::vector<long> DoneIndices(long run);
  // How many there are, in constant memory (a million-rollout run checks it at its end).
  long CountDone(long run);

  // Queues one result (case and result rows); written at the next Commit, which also
  // happens automatically every `batch` rows. A process killed between commits loses
  // only the queued rows.
  void Add(long run, const RolloutResult& result);
  void Commit();

  // All results of a run in index order.
  std::vector<RolloutResult> Results(long run);
  // The same, one at a time, in memory that does not grow with the run.
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
