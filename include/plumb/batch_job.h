// A batch job (a rollout batch or a sweep) as every front end runs it: the spec from the
// user's text, the run opened or resumed in a results store, the tally of its rows, the commit
// when it stops, and what it has to say as notices (topic NoticeTopic::kBatch). The plumb
// command and plumb.rollout/plumb.sweep parse their options, call this and present what it
// returns; the words that name their options (a flag, a keyword) are theirs (BatchWords).
//
// Example:
//   plumb::BatchText text;
//   text.randomize = {"body_mass[*]=*U(0.9,1.1)"};
//   text.metrics = {"energy_drift"};
//   plumb::RolloutSpec spec = plumb::ParseRolloutSpec(model, plumb::RolloutSpec{}, text);
//   plumb::BatchJob job(db, /*resume=*/true, plumb::RolloutRunInfo(model, spec, origin, db),
//                       plumb::BatchWords{}, &notices);
//   job.Resume(plumb::ShardSize(spec), plumb::InShard(spec), [](const plumb::RolloutResult&) {});
//   spec.skip = job.done();
//   job.Run([&] { plumb::Rollout(model, spec, [&](const auto& r) { job.Add(r); }, stop); });
//   job.Complete(spec.count);
//
// Thread-safety: a BatchJob is used from one thread at a time (Add from the thread that emits
// the rows); the notices may be given to a Notices that other threads read.

#ifndef PLUMB_INCLUDE_PLUMB_BATCH_JOB_H_
#define PLUMB_INCLUDE_PLUMB_BATCH_JOB_H_

#include <functional>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include "plumb/batch.h"
#include "plumb/model.h"
#include "plumb/notice.h"
#include "plumb/rollout.h"
#include "plumb/stored_run.h"
#include "plumb/sweep.h"

namespace plumb {

// How a front end names a batch's options in what the job says: the CLI's flags, Python's
// keywords. The defaults are neutral words.
struct BatchWords {
  std::string store = "store";        // the store's option: the CLI's flag, Python's db
  std::string resume = "resume";      // asking to resume: the CLI's flag, "resume=True"
  std::string go_on = "resume it";    // how to go on after a stop: "call it again with ..."
  std::string vary = "vary";          // a sweep axis's option, naming its warnings
};

// A batch's options as the user wrote them (each list in order).
struct BatchText {
  std::vector<std::string> randomize;  // a rollout's PATH=DIST
  std::vector<std::string> vary;       // a sweep's PATH=V1,V2,... or PATH=START:STOP:COUNT
  std::vector<std::string> metrics;    // PATH@T, period(PATH), ...
  std::string shard;                   // a rollout's "I/N"; empty: `spec`'s shard stands
};

// `spec` (its start, count, until, threads, seed, ctrl_noise, shard as given) with the
// randomizations, metrics and shard parsed from `text`, validated (ValidateRolloutSpec). With
// control noise, SayCtrlNoiseCentre says to `notices` where the noise's centre is not what the
// user's start gives.
// @throws ArgumentError naming the argument ("randomize", "metric", "shard") and the text for a
// bad one; PathError for a path the model does not have.
RolloutSpec ParseRolloutSpec(const Model& model, RolloutSpec spec, const BatchText& text,
                             Notices* notices = nullptr);

// Control noise is centred on the start's ctrl (CtrlNoiseCentre). A note (topic kStart) when
// the centre is not the user's: a start that sets no ctrl while position servos read ctrl 0 as
// a target (no keyframe, no ctrl set), or a start ctrl outside its ctrlrange (clamped).
// Nothing without control noise.
void SayCtrlNoiseCentre(const Model& model, const RolloutSpec& spec, Notices* notices);
// `spec` (its start, threads, until) with the axes and metrics parsed from `text`, validated
// (ValidateSweepSpec). An axis's assignment warnings (a ctrl outside its range) go to `notices`
// (topic kStart), named "WORDS.vary 'TEXT'". @throws as ParseRolloutSpec ("vary", "metric").
SweepSpec ParseSweepSpec(const Model& model, SweepSpec spec, const BatchText& text,
                         const BatchWords& words = {}, Notices* notices = nullptr);

// Whether a stored row is one of `spec`'s shard's.
std::function<bool(const RolloutResult&)> InShard(const RolloutSpec& spec);

// One batch's run: its place in a results store (none without a store file) and the tally of
// its rows, those stored before a resume and those run now.
class BatchJob {
 public:
  // Opens the run `info` describes in the store `db` or begins it (OpenStoredRun). When a
  // resume begins it, a note says so ("'r.sqlite' holds no rollout run yet; starting one").
  // @throws ArgumentError "store" when the store holds the run and `resume` is false (naming
  // WORDS.resume), and as OpenStoredRun.
  BatchJob(const std::string& db, bool resume, const RunInfo& info, BatchWords words = {},
           Notices* notices = nullptr);

  // The indices the store holds (sorted): what the run skips.
  const std::vector<long>& done() const { return stored_.done; }
  bool stored() const { return stored_.store != nullptr; }
  const std::string& db() const { return db_; }
  // "rollouts" or "cases": how the job counts its rows.
  const std::string& unit() const { return unit_; }

  // Counts each stored row that is `mine` as resumed and hands it to `row`; when there are
  // any, a note says "N of TOTAL rollouts are stored in 'r.sqlite'; running the rest" (or
  // that all are stored and nothing is left to run).
  void Resume(long total, const std::function<bool(const RolloutResult&)>& mine,
              const std::function<void(const RolloutResult&)>& row);
  // A row run now: tallied and stored.
  void Add(const RolloutResult& r);

  // Runs `work` (the rows it makes reach Add) and times it. On a stop request (Interrupted)
  // every finished row is committed and Interrupted is thrown again with StopMessage (saying
  // `finished()` when given).
  void Run(const std::function<void()>& work,
           const std::function<std::string()>& finished = nullptr);
  // Commits what the store holds so far.
  void Commit();
  // "12 rollouts finished": the rows run now.
  std::string Finished() const;
  // What a stop says: `stopped` (the Interrupted's text), `finished` (default: "12 rollouts
  // finished") and, with a store, that they are stored and how to go on (WORDS.go_on).
  std::string StopMessage(const std::string& stopped, const std::string& finished = "") const;
  // Commits and marks the run finished when the store holds all `total` rows.
  void Complete(long total);

  const BatchSummary& summary() const { return summary_; }
  // How long Run took (s).
  double seconds() const { return seconds_; }

 private:
  StoredRun stored_;
  std::string db_, unit_;
  BatchWords words_;
  Notices* notices_;
  BatchSummary summary_;
  double seconds_ = 0;
};

// What a sweep says about its measurements, as notices (topic kBatch): each reason a metric
// could not be measured, as it first happens (a warning "case 3, qpos[hinge]@2: REASON"); at
// the end how often each recurred, how many measurements could not be made, and a note per axis
// that changed nothing (SweepEffects). `spec` must outlive it.
class SweepNotices {
 public:
  // `model` (may be null; it must outlive this) gives the effects' notes their reasons.
  SweepNotices(const SweepSpec& spec, Notices* notices, const Model* model = nullptr);
  // A case run now (its row: SweepCaseResult).
  void See(const SweepCase& c, const RolloutResult& row);
  // A case a resume found stored: for the effects only (its reasons were said when it ran).
  void SeeStored(const RolloutResult& row) { effects_.See(row); }
  // Says the counts and the effects' notes, and returns those notes.
  std::vector<std::string> Finish();

 private:
  const SweepSpec& spec_;
  Notices* notices_;
  SweepEffects effects_;
  long cases_ = 0, failed_ = 0;
  std::map<std::pair<std::size_t, std::string>, long> problems_;  // (metric, reason): cases
};

}  // namespace plumb

#endif  // PLUMB_INCLUDE_PLUMB_BATCH_JOB_H_
