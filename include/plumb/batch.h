// What every front end of the batch commands (plumb rollout and sweep, plumb.rollout and
// plumb.sweep in Python) shares, written once: the config line that names a batch in a results
// store (so --resume from one continues a run of the other), the store record it opens, its
// rows as the JSON `--format json` prints, a sweep case as a store row, and the summary.
//
// Example:
//   plumb::RolloutSpec spec = ...;
//   plumb::BatchOrigin origin{"arm.xml", {"plumb", "rollout", "arm.xml"},
//                             plumb::StartConfig(model, plumb::StartSpec{})};
//   plumb::StoredRun run = plumb::OpenStoredRun(db, resume, plumb::RolloutRunInfo(model, spec,
//                                                                               origin, db));
//   plumb::RolloutJson json(plumb::ParameterNames(spec), {"energy_drift"});
//   plumb::BatchSummary summary(spec.metrics.size());
//   std::string text = json.Begin();
//   plumb::Rollout(model, spec, [&](const plumb::RolloutResult& r) {
//     summary.Add(r);
//     text += json.Row(r);
//   });
//   text += json.End();
//
// Thread-safety: the functions only read their arguments; a RolloutJson, SweepJson or
// BatchSummary is used from one thread at a time. Nothing throws but std::bad_alloc, except
// where said.

#ifndef PLUMB_INCLUDE_PLUMB_BATCH_H_
#define PLUMB_INCLUDE_PLUMB_BATCH_H_

#include <map>
#include <string>
#include <string_view>
#include <vector>

#include "plumb/keyframe.h"
#include "plumb/model.h"
#include "plumb/notice.h"
#include "plumb/path.h"
#include "plumb/rollout.h"
#include "plumb/statistics.h"
#include "plumb/store.h"
#include "plumb/sweep.h"

namespace plumb {

// The part of a batch's config line that says where its runs start: the start state the model
// restores (StartStateConfig), " keyframe=NAME", " pose=PATH=V,..." for each assignment of the
// pose file and the whole qpos as resolved (an edited pose file is another config), and
// " set=TEXT" per set assignment as typed, in that order. @throws as StartAssignments does for
// the pose file and the qpos.
std::string StartConfig(const Model& model, const StartSpec& start);

// Who asked for a batch and where its runs start: what a results store records beside its rows.
struct BatchOrigin {
  std::string model_file;            // the model as the caller named it
  std::vector<std::string> command;  // the command line's words, or a Python call's text
  std::string start;                 // StartConfig
};

// The canonical config line of a rollout batch and of a sweep: everything that decides their
// rows (the model as `model_hash`, the options, the start, the randomizations, axes and
// metrics as typed, the versions of plumb and MuJoCo), so the same line means the same rows.
std::string RolloutConfig(const RolloutSpec& spec, const std::string& model_hash,
                          const std::string& start);
std::string SweepConfig(const SweepSpec& spec, const std::string& model_hash,
                        const std::string& start);

// The record of a rollout batch or a sweep for OpenStoredRun (stored_run.h): its config,
// origin, parameter and metric names and count. The model is hashed only when `db` (the store
// file) is not empty: hashing a big mesh model costs a tenth of a second. @throws ValueError
// from CaseCount for a sweep too large to run.
RunInfo RolloutRunInfo(const Model& model, const RolloutSpec& spec, const BatchOrigin& origin,
                       const std::string& db);
RunInfo SweepRunInfo(const Model& model, const SweepSpec& spec, const BatchOrigin& origin,
                     const std::string& db);

// Sets spec->shard_index and shard_count from "I/N" (0 <= I < N).
// @throws ArgumentError "shard" naming the text otherwise.
void ParseShard(std::string_view text, RolloutSpec* spec);

// The names of a sweep's axes (their paths, as the JSON and the store name them).
std::vector<std::string> AxisNames(const SweepSpec& spec);
// A sweep case as a results-store row: its axis values as parameters, one metric each (NaN when
// not measured), diverged when a metric's run diverged, and the reasons joined by "; ".
RolloutResult SweepCaseResult(const SweepSpec& spec, const SweepCase& c);

// A rollout batch as `plumb rollout --format json` prints it: "[", one object a rollout
// ({"rollout", "params", "metrics" (null where unmeasured), "diverged", "diverged_time" when it
// did, "problem" when there is one}), "]". Begin, then Row per rollout in order, then End; the
// texts joined are the document.
class RolloutJson {
 public:
  RolloutJson(std::vector<std::string> parameters, std::vector<std::string> metrics);
  std::string Begin() const;
  std::string Row(const RolloutResult& r);
  std::string End() const;

 private:
  std::vector<std::string> parameters_, metrics_;
  long rows_ = 0;
};

// A sweep as `plumb sweep --format json` prints it: {"model", "vary" (the axes), "metrics",
// "cases": one object a case ({"case", "values", "metrics" (null where unmeasured), "problems"
// when a metric could not be measured})}. Used as RolloutJson is.
class SweepJson {
 public:
  SweepJson(std::string model_file, std::vector<std::string> axes,
            std::vector<std::string> metrics);
  std::string Begin() const;
  // Case `index` with its axis values and one measurement per metric.
  std::string Row(long index, const std::vector<double>& values,
                  const std::vector<Measurement>& metrics);
  std::string End() const;

 private:
  std::string model_file_;
  std::vector<std::string> axes_, metrics_;
  long rows_ = 0;
};

// Watches whether each axis of a sweep changes anything: the cases where every other axis takes
// its first value are a line along that axis (fewer than the sum of the axes' sizes, so memory
// stays small however many cases run). An axis along which every metric is bit-identical gets
// a note with the likely reason, instead of a table that silently shows no effect. `spec` must
// outlive the watch.
class SweepEffects {
 public:
  // With `model` (it must outlive the watch) the reason reads the model: a geom's friction
  // judged against the priority of the geoms it may touch.
  explicit SweepEffects(const SweepSpec& spec, const Model* model = nullptr);

  // Axes with more values than this are not watched: their line would cost memory that grows
  // with the sweep (a range of a million values is not a question of "no effect").
  static constexpr std::size_t kMostWatched = 4096;

  // One case as a store row (SweepCaseResult: its index and metrics), in any order.
  void See(const RolloutResult& row);

  // One note per axis whose line was seen whole and holds values that changed nothing
  // (bit-identical metrics for different values), naming the axis as "vary 'TEXT'" and what
  // may be the reason.
  std::vector<std::string> Notes() const;

 private:
  const SweepSpec& spec_;
  const Model* model_;
  std::vector<std::map<std::size_t, std::vector<double>>> lines_;
};

// Watches whether a rollout batch's randomizations change anything: when every measured
// rollout (at least two) gave bit-identical metrics, each randomization gets a note with the
// likely reason (as SweepEffects's). `spec` and `model` (may be null) must outlive the watch.
class RolloutEffects {
 public:
  explicit RolloutEffects(const RolloutSpec& spec, const Model* model = nullptr);
  // One rollout's row (run now or stored), in any order.
  void See(const RolloutResult& row);
  // "randomize 'TEXT' changed no metric: ... REASON", one a randomization; none when the rows
  // differ.
  std::vector<std::string> Notes() const;
  // Adds the notes to `notices` (topic kBatch) and returns them.
  std::vector<std::string> Finish(Notices* notices) const;

 private:
  const RolloutSpec& spec_;
  const Model* model_;
  std::vector<double> first_;  // the first measured row's metrics
  long measured_ = 0;
  bool differ_ = false;
};

// The summary of a batch: how many rows were run now and how many were stored before a resume,
// how many diverged, and each metric's statistics.
struct BatchSummary {
  explicit BatchSummary(std::size_t metrics) : metrics(metrics) {}
  // One row (stored before or run now: the caller counts which in `resumed` and `run_now`).
  void Add(const RolloutResult& r);
  // What plumb rollout prints after its rows: "N rollouts, D diverged (P%), R rollouts/s" (with
  // how many were stored before a resume), then per metric "NAME: n .. mean .. std .. min .. q05
  // .. median .. q95 .. max .." (or that none was measured). `unit` names the rows ("rollouts",
  // "cases"), `seconds` the time the rows run now took.
  std::string Text(const std::vector<std::string>& names, const std::string& unit,
                   double seconds) const;

  std::vector<SummaryStatistics> metrics;
  long diverged = 0, run_now = 0, resumed = 0;
};

}  // namespace plumb

#endif  // PLUMB_INCLUDE_PLUMB_BATCH_H_
