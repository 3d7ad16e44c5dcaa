// A time budget as a stop request (include/plumb/stop.h).

#include "plumb/stop.h"

#include <chrono>

namespace plumb {

StopTimer::StopTimer(StopSource source, double seconds)
    : source_(std::move(source)), seconds_(seconds) {
  if (seconds <= 0) return;
  watcher_ = std::thread([this] {
    std::unique_lock<std::mutex> lock(mutex_);
    auto deadline = std::chrono::steady_clock::now() +
                    std::chrono::duration_cast<std::chrono::steady_clock::duration>(
                        std::chrono::duration<double>(seconds_));
    if (done_.wait_until(lock, deadline, [this] { return finished_; })) return;
    spent_ = true;
    source_.RequestStop();
  });
}

StopTimer::~StopTimer() { Finish(); }

void StopTimer::Finish() {
  if (!watcher_.joinable()) return;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    finished_ = true;
  }
  done_.notify_all();
  watcher_.join();
}

}  // namespace plumb
