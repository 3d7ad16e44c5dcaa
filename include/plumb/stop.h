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
// (the plumb command stops the call it runs this way on SIGINT and SIGTERM). Nothing here
// throws, except the allocation in StopSource's constructor (std::bad_alloc).

#ifndef PLUMB_INCLUDE_PLUMB_STOP_H_
#define PLUMB_INCLUDE_PLUMB_STOP_H_

#include <atomic>
#include <memory>
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

}  // namespace plumb

#endif  // PLUMB_INCLUDE_PLUMB_STOP_H_
