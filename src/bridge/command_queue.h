// The commands waiting for their lockstep period: each command that arrives is one period, in
// the order they came. The queue is bounded: when it is full the oldest waiting command is
// dropped (the controller has run that far ahead of the simulation; its latest word counts
// most), and the caller counts and logs the drop.

#ifndef PLUMB_SRC_BRIDGE_COMMAND_QUEUE_H_
#define PLUMB_SRC_BRIDGE_COMMAND_QUEUE_H_

#include <cstddef>
#include <deque>
#include <utility>
#include <vector>

#include "bridge/pd_law.h"

namespace plumb::bridge {

// A command that arrived: one lockstep period.
struct Arrived {
  std::vector<MotorCommand> command;  // empty: lost (bad CRC, NaN, injected drop), the old
                                      // command stays in force for its period
  double delay = 0;                   // injected latency, s of simulated time
};

class CommandQueue {
 public:
  explicit CommandQueue(std::size_t capacity) : capacity_(capacity < 1 ? 1 : capacity) {}

  // Appends `a`; returns false when the queue was full and its oldest command was dropped to
  // make room.
  bool Push(Arrived a) {
    bool room = queue_.size() < capacity_;
    if (!room) queue_.pop_front();
    queue_.push_back(std::move(a));
    return room;
  }

  // The oldest waiting command, taken out. The queue must not be empty.
  Arrived Pop() {
    Arrived a = std::move(queue_.front());
    queue_.pop_front();
    return a;
  }

  bool empty() const { return queue_.empty(); }
  std::size_t size() const { return queue_.size(); }
  std::size_t capacity() const { return capacity_; }

 private:
  std::size_t capacity_;
  std::deque<Arrived> queue_;
};

}  // namespace plumb::bridge

#endif  // PLUMB_SRC_BRIDGE_COMMAND_QUEUE_H_
