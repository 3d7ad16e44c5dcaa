// Stopping a long call. A StopSource owns one stop request; each long call (Run, Verify,
// Audit, Converge, snapshots, Sweep, Rollout, Identify, Replay, the bridge) takes a StopToken
// of it, looks at it between steps, and ends with plumb::Interrupted soon after the request
// is made, keeping what it had finished (a sweep's or a rollout's rows before it). Requests
// are per source: stopping one call does not stop a call another thread made with another
// source. A default StopToken never asks to stop.
//
// Thread-safety: RequestStop, Clear and stop_requested may be called from any thread, at
// any time, on copies of one source or token. RequestStop is async-signal-safe (one
// lock-free atomic store): a signal handler may call it on a StopSource that outlives it
// (the plumb command stops the call it runs this way on SIGINT and SIGTERM). A StopTimer is
// used from the thread that made it. Nothing here throws, except the allocation in
// StopSource's constructor (std::bad_alloc) and StopTimer's std::system_error when no thread
// can be started.

#ifndef PLUMB_INCLUDE_PLUMB_STOP_H_
#define PLUMB_INCLUDE_PLUMB_STOP_H_

#include <atomic>
#include <condition_variable>
#include <memory>
#include <mutex>
#include <thread>
#include <utility>

namespace plumb {

class StopSource;

// What a long call holds: whether its caller has asked it to stop. Cheap to copy.
class StopToken {
 public:
  StopToken() = default;  // never asks to stop

  bool stop_requested() const noexcept {
    return flag_ != nullptr && flag_->load(std::memory_order_relaxed);
  }

 private:
  friend class StopSource;
  explicit StopToken(std::shared_ptr<const std::atomic<bool>> flag) : flag_(std::move(flag)) {}
  std::shared_ptr<const std::atomic<bool>> flag_;
};

// What the caller holds: one stop request, unset when made. Copies share the request.
class StopSource {
 public:
  StopSource() : flag_(std::make_shared<std::atomic<bool>>(false)) {}

  StopToken token() const { return StopToken(flag_); }
  // Asks every call holding a token of this source to stop. It stays asked until Clear.
  // Returns whether this call made the request (false: it had been made before).
  bool RequestStop() const noexcept { return !flag_->exchange(true, std::memory_order_relaxed); }
  // Withdraws the request (a caller that handled a stop and goes on with new calls).
  void Clear() const noexcept { flag_->store(false, std::memory_order_relaxed); }
  bool stop_requested() const noexcept { return flag_->load(std::memory_order_relaxed); }

 private:
  static_assert(std::atomic<bool>::is_always_lock_free,
                "RequestStop must be async-signal-safe: a lock-free store");
  std::shared_ptr<std::atomic<bool>> flag_;
};

// A time budget: requests `source`'s stop once `seconds` of wall-clock time have passed, so
// a long call ends as if its caller had stopped it, keeping what it finished. A watcher thread
// waits for the deadline; Finish (or the destructor) ends the watch.
class StopTimer {
 public:
  StopTimer(StopSource source, double seconds);  // seconds <= 0: no budget, no thread
  ~StopTimer();
  StopTimer(const StopTimer&) = delete;
  StopTimer& operator=(const StopTimer&) = delete;
  // Ends the watch (the call is over). When the deadline passed at that very moment, the
  // request it made stays: Spent() says so, and the caller may Clear it.
  void Finish();
  // Whether the deadline passed and the timer requested the stop.
  bool Spent() const { return spent_.load(); }
  double seconds() const { return seconds_; }

 private:
  StopSource source_;
  double seconds_;
  std::atomic<bool> spent_{false};
  std::mutex mutex_;
  std::condition_variable done_;
  bool finished_ = false;
  std::thread watcher_;
};

}  // namespace plumb

#endif  // PLUMB_INCLUDE_PLUMB_STOP_H_
