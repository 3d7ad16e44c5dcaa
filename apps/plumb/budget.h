// Budgets: plumb run's --max-seconds / --max-rows and its progress bar, and how long a batch
// command (sweep, rollout) has left (the estimate itself is plumb/run_estimate.h).

#ifndef PLUMB_APPS_PLUMB_BUDGET_H_
#define PLUMB_APPS_PLUMB_BUDGET_H_

#include <chrono>
#include <memory>
#include <string>
#include <vector>

#include "cli_common.h"
#include "plumb/model.h"
#include "plumb/path.h"
#include "plumb/run.h"
#include "plumb/run_estimate.h"
#include "plumb/sample_writer.h"

namespace plumb::cli {

struct RunBudget {
  double max_seconds = 0;  // wall clock; 0: none
  long max_rows = 0;       // sample rows written; 0: none
};

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

}  // namespace plumb::cli

#endif  // PLUMB_APPS_PLUMB_BUDGET_H_
