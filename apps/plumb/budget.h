// Cost before it is spent: plumb run's estimate of time and disk from a short probe, its
// progress bar and its --max-seconds / --max-rows budgets; the wall-clock budget of the
// batch commands (sweep, rollout: --max-seconds).

#ifndef PLUMB_APPS_PLUMB_BUDGET_H_
#define PLUMB_APPS_PLUMB_BUDGET_H_

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "cli_common.h"
#include "plumb/model.h"
#include "plumb/path.h"
#include "plumb/run.h"
#include "plumb/sample_writer.h"

namespace plumb::cli {

struct RunBudget {
  double max_seconds = 0;  // wall clock; 0: none
  long max_rows = 0;       // sample rows written; 0: none
};

// What a run will cost, from a probe of its first steps on a copy of the model.
struct RunEstimate {
  long steps = 0, rows = 0;
  double seconds = 0;  // wall time of the steps and rows
  double bytes = 0;    // output size (0 when the run writes a table to a terminal)
  long probe_steps = 0;
};

// Times up to 200000 steps (at most about 0.1 s) of `model` with `sets` applied on a copy, and
// one row written in `format`. Never changes `model`.
RunEstimate EstimateRun(const Model& model, const std::vector<Assignment>& sets,
                        const RunSpec& spec, SampleFormat format);

// "2.0e+07 steps and 200001 rows: about 14 s and 48 MB of csv" for the log line.
std::string DescribeEstimate(const RunEstimate& e, const std::string& format);

// Wraps the run's writer and watches the budgets and the signals: when a budget is spent it
// raises the stop flag the run watches, so the run ends between steps with every row it
// wrote whole. Draws the progress bar on a terminal.
class BudgetedRun : public SampleSink {
 public:
  BudgetedRun(SampleSink& writer, const RunBudget& budget, long steps, bool progress);
  // Installs the stop request and the step hook in `spec`.
  void Watch(RunSpec& spec);
  void Begin(const std::vector<Path>& columns) override { writer_.Begin(columns); }
  void Sample(const std::vector<double>& row) override;
  void End() override;
  // Why the run stopped early ("" when it did not, or a signal stopped it).
  const std::string& spent() const { return spent_; }
  long rows() const { return rows_; }

 private:
  void AfterStep(long step);

  SampleSink& writer_;
  RunBudget budget_;
  StopSource stop_;  // the budget's, or the command's when a signal asked
  std::chrono::steady_clock::time_point start_ = std::chrono::steady_clock::now();
  std::unique_ptr<ProgressBar> bar_;
  long rows_ = 0;
  std::string spent_;
};

// "512 B", "48 kB", "570 MB", "1.2 GB".
std::string FormatBytes(double bytes);

// "40 s", "12 min", "3.5 h", "2.1 days".
std::string FormatDuration(double seconds);

// A long batch says how long once it knows (after 2 s), when the rest takes more than a
// minute, and how to stop it without losing work:
// "plumb: at 5.2e+04 rollouts/s the rest takes about 12 min; Ctrl-C or --max-seconds stops it
// and keeps what finished (then --resume goes on)".
class EtaNote {
 public:
  EtaNote(std::string unit, bool stored, ProgressBar& progress)
      : unit_(std::move(unit)), stored_(stored), progress_(progress) {}
  // After each item: `done` so far in this process, `left` still to do.
  void See(long done, long left);

 private:
  std::string unit_;
  bool stored_;
  ProgressBar& progress_;
  std::chrono::steady_clock::time_point start_ = std::chrono::steady_clock::now();
  bool told_ = false;
};

// --max-seconds of a batch command: a watcher requests the command's stop (CommandStop) when
// the budget is spent, so the batch stops as on Ctrl-C, between cases, keeping (printing and
// storing) what finished; KeepFinishedOnStop then ends it normally rather than with exit 130.
class WallClockBudget {
 public:
  explicit WallClockBudget(double seconds);  // 0: no budget
  ~WallClockBudget();
  WallClockBudget(const WallClockBudget&) = delete;
  WallClockBudget& operator=(const WallClockBudget&) = delete;
  // Ends the watch (the batch is over); a budget spent at that very moment requested the
  // stop for nothing, which is withdrawn again.
  void Finish();
  // Whether the budget stopped the batch (and not a signal).
  bool Spent() const { return spent_.load(); }
  double seconds() const { return seconds_; }

 private:
  double seconds_;
  std::atomic<bool> spent_{false};
  std::mutex mutex_;
  std::condition_variable done_;
  bool finished_ = false;
  std::thread watcher_;
};

}  // namespace plumb::cli

#endif  // PLUMB_APPS_PLUMB_BUDGET_H_
