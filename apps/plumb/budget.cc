#include "budget.h"

#include <fmt/format.h>

#include <cstdio>
#include <cstdlib>

#include "plumb/error.h"

namespace plumb::cli {

BudgetedRun::BudgetedRun(SampleSink& writer, const RunBudget& budget, long steps, bool progress)
    : writer_(writer), budget_(budget) {
  if (progress) bar_ = std::make_unique<ProgressBar>(steps, "steps");
}

void BudgetedRun::Watch(RunSpec& spec) {
  spec.stop = stop_.token();
  spec.after_step = [this](const mjData*, long step) { AfterStep(step); };
}

void BudgetedRun::AfterStep(long step) {
  if (CommandStop().stop_requested()) stop_.RequestStop();
  if (step % 256 != 0) return;
  if (bar_) bar_->Update(step);
  if (budget_.max_seconds > 0 && spent_.empty()) {
    double seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
    if (seconds >= budget_.max_seconds) {
      spent_ = fmt::format("--max-seconds {:g}", budget_.max_seconds);
      stop_.RequestStop();
    }
  }
}

void BudgetedRun::Sample(const std::vector<double>& row) {
  writer_.Sample(row);
  ++rows_;
  if (budget_.max_rows > 0 && rows_ >= budget_.max_rows && spent_.empty()) {
    spent_ = fmt::format("--max-rows {}", budget_.max_rows);
    stop_.RequestStop();
  }
}

void BudgetedRun::End() {
  if (bar_) bar_->Finish();
  writer_.End();
}

void EtaNote::See(long done, long left) {
  if (told_ || left <= 0 || done <= 0) return;
  double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
  if (seconds <= 2) return;
  told_ = true;
  double eta = seconds / static_cast<double>(done) * static_cast<double>(left);
  if (eta <= 60) return;
  progress_.Clear();
  std::fprintf(stderr,
               "plumb: at %.3g %s/s the rest takes about %s; Ctrl-C or --max-seconds stops it and "
               "keeps what finished%s\n",
               done / seconds, unit_.c_str(), FormatDuration(eta).c_str(),
               stored_ ? " (then --resume goes on)" : "");
}

}  // namespace plumb::cli
