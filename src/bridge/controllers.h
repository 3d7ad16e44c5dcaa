// Who drives the robot (plumb/bridge.h, RunBridge): one controller at a time. The DDS writer
// whose good command came first is in charge; another writer's commands are foreign, dropped
// and counted (and said once a writer), until the one in charge falls silent for the
// watchdog's timeout of wall time; then the next writer with a good command takes over.
// Controllers are named in the order they were first heard ("controller 1"): a DDS writer's
// handle differs from run to run, and a lockstep log must repeat bit for bit.

#ifndef PLUMB_SRC_BRIDGE_CONTROLLERS_H_
#define PLUMB_SRC_BRIDGE_CONTROLLERS_H_

#include <dds/dds.h>
#include <fmt/format.h>

#include <chrono>
#include <cstddef>
#include <functional>
#include <map>
#include <set>
#include <string>
#include <utility>

namespace plumb::bridge {

class Controllers {
 public:
  using Clock = std::chrono::steady_clock;
  using Say = std::function<void(const std::string&)>;  // an event for the log

  // `timeout`: s of wall time the one in charge may be silent before another takes over.
  Controllers(double timeout, Say say) : timeout_(timeout), say_(std::move(say)) {}

  // Starts the silence clock (the run's first state went out).
  void Start() { last_good_ = Clock::now(); }

  // Whether a command from `writer` comes from a controller other than the one in charge,
  // while that one is alive; counts it in `*foreign` when it does.
  bool Foreign(dds_instance_handle_t writer, long* foreign) {
    if (owner_ == 0 || writer == owner_ || OwnerSilent()) return false;
    ++*foreign;
    if (logged_.insert(writer).second) {
      say_(
          fmt::format("a second controller ({}) publishes on rt/lowcmd while {} is in charge: "
                      "its commands are dropped until that one falls silent for {:g} ms",
                      Name(writer), Name(owner_), timeout_ * 1000));
    }
    return true;
  }

  // A good command from `writer`: it is in charge from now on (it already was, or it is the
  // first, or the one in charge fell silent).
  void Good(dds_instance_handle_t writer) {
    if (writer != owner_) {
      if (owner_ == 0) {
        say_(Name(writer) + " is in charge");
      } else {
        say_(fmt::format("{} takes over from {}, silent for {:.0f} ms", Name(writer), Name(owner_),
                         SilentFor() * 1000));
      }
      owner_ = writer;
      logged_.erase(writer);
    }
    last_good_ = Clock::now();
    heard_ = true;
  }

  // Whether a good command has come since the start.
  bool heard() const { return heard_; }
  // When the last good command came (or the run started).
  Clock::time_point last_good() const { return last_good_; }
  // s of wall time since then.
  double SilentFor() const {
    return std::chrono::duration<double>(Clock::now() - last_good_).count();
  }
  bool OwnerSilent() const { return SilentFor() > timeout_; }

 private:
  std::string Name(dds_instance_handle_t writer) {
    auto [at, fresh] = numbers_.emplace(writer, numbers_.size() + 1);
    return fmt::format("controller {}", at->second);
  }

  double timeout_;
  Say say_;
  Clock::time_point last_good_ = Clock::now();
  bool heard_ = false;
  dds_instance_handle_t owner_ = 0;         // the one in charge (0: none yet)
  std::set<dds_instance_handle_t> logged_;  // other writers already said
  std::map<dds_instance_handle_t, std::size_t> numbers_;
};

}  // namespace plumb::bridge

#endif  // PLUMB_SRC_BRIDGE_CONTROLLERS_H_
