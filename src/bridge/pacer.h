// Pacing a loop to the wall clock, and saying how well it kept up: the realtime factor and the
// periods that started late.
//
// A period is due one control period after the one before. The pacer catches up at most one
// period of delay; a period that starts more than one period after it was due is late (its
// state goes out at least a whole period behind the wall clock), and the time it lost is not
// made up: the simulation falls behind the wall clock by that much.

#ifndef PLUMB_SRC_BRIDGE_PACER_H_
#define PLUMB_SRC_BRIDGE_PACER_H_

#include <algorithm>
#include <chrono>

namespace plumb::bridge {

class Pacer {
 public:
  using Clock = std::chrono::steady_clock;

  explicit Pacer(double period) : period_(period) {}

  // When the next period is due. Before the first period, and after Restart, it is due at once.
  Clock::time_point due(Clock::time_point now) const { return started_ ? due_ : now; }

  // Records that a period starts at `now` (after waiting until due()); returns how late it
  // started, s (0 when on time or early).
  double Start(Clock::time_point now) {
    if (!started_) due_ = now;
    started_ = true;
    double lateness = std::max(0.0, std::chrono::duration<double>(now - due_).count());
    if (lateness > period_) {
      ++late_;
      worst_ = std::max(worst_, lateness);
    }
    auto period =
        std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(period_));
    due_ = std::max(due_ + period, now - period);  // at most one period caught up
    return lateness;
  }

  // The next period is due at once, not late: pacing resumes after unpaced periods (lockstep
  // between two spells of watchdog damping).
  void Restart() { started_ = false; }

  bool Late(double lateness) const { return lateness > period_; }
  long late_periods() const { return late_; }
  double worst_lateness() const { return worst_; }  // s, of the late periods (0: none)

 private:
  double period_;
  bool started_ = false;
  Clock::time_point due_{};
  long late_ = 0;
  double worst_ = 0;
};

}  // namespace plumb::bridge

#endif  // PLUMB_SRC_BRIDGE_PACER_H_
