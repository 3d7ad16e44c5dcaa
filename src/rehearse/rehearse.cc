// The rehearsal (plumb/rehearse.h): the bridge on the calling thread, the client started once
// the bridge is up, and a watcher thread that reads the client's output and ends the run when
// the client ends early, never commands, or the caller asks to stop.

#include "plumb/rehearse.h"

#include <signal.h>

#include <atomic>
#include <chrono>
#include <cmath>
#include <exception>
#include <memory>
#include <mutex>
#include <thread>

#include <fmt/format.h>

#include "plumb/error.h"
#include "plumb/run.h"
#include "rehearse/client_process.h"
#include "rehearse/client_watch.h"
#include "rehearse/rehearsal_rows.h"
#include "rehearse/rehearsal_tally.h"

namespace plumb {
namespace {

double Now() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch())
      .count();
}

// The client's command with "{domain}" replaced by the bridge's domain id.
std::string ClientCommand(std::string command, std::uint32_t domain) {
  const std::string key = "{domain}";
  for (std::size_t at = command.find(key); at != std::string::npos;
       at = command.find(key, at + 1)) {
    command.replace(at, key.size(), std::to_string(domain));
  }
  return command;
}

// Everything the run watches: the observer the bridge calls (on its thread), and the watcher
// thread's side (the client's process, once started).
class Rehearsal : public BridgeObserver {
 public:
  Rehearsal(const RehearsalSpec& spec, const StopToken& caller)
      : spec_(spec), caller_(caller) {}

  ~Rehearsal() override { Join(); }

  // The watcher: forwards the caller's stop to the bridge, and once the client runs, reads
  // its output and ends the run when it ends or sends nothing in time.
  void Watch() {
    watcher_ = std::thread([this] {
      while (!finished_.load()) {
        if (caller_.stop_requested()) bridge_stop_.RequestStop();
        if (!started_.load(std::memory_order_acquire)) {
          std::this_thread::sleep_for(std::chrono::milliseconds(20));
          continue;
        }
        if (client_->Poll(0.02)) {
          if (!ended_early_.exchange(true)) ended_time_ = last_time_.load();
          bridge_stop_.RequestStop();
          return;
        }
        if (!commanded_.load() &&
            Now() - client_start_ > spec_.client.first_command_timeout) {
          never_commanded_ = true;
          bridge_stop_.RequestStop();
          return;
        }
      }
    });
  }

  void Join() {
    finished_ = true;
    if (watcher_.joinable()) watcher_.join();
  }

  StopToken bridge_token() const { return bridge_stop_.token(); }

  void Started(const Model& model, const std::vector<BridgeMotorInfo>& motors) override {
    watch_ = std::make_unique<internal::ClientWatch>(model, motors, spec_.config);
    tally_ = std::make_unique<internal::RehearsalTally>(spec_.assertions, motors);
    std::vector<std::pair<std::string, std::string>> env = spec_.client.environment;
    env.insert(env.begin(), {"PLUMB_BRIDGE_DOMAIN", std::to_string(spec_.config.domain)});
    env.insert(env.begin(), {"CYCLONEDDS_URI", BridgeLoopbackConfig()});
    try {
      client_ = std::make_unique<internal::ClientProcess>(
          ClientCommand(spec_.client.command, spec_.config.domain), spec_.client.directory, env,
          spec_.client.tail_lines, spec_.client.output);
    } catch (...) {
      start_error_ = std::current_exception();
      bridge_stop_.RequestStop();
      return;
    }
    client_start_ = Now();
    started_.store(true, std::memory_order_release);
  }

  void Commanded(double t, double wall, const std::vector<BridgeCommandSlot>& slots) override {
    if (watch_) watch_->Commanded(t, wall, slots);
    commanded_ = true;
  }

  void Published(const Model& model, const Data& data,
                 const std::vector<BridgeMotorSample>& motors) override {
    if (watch_) watch_->Published(model, data, motors);
    if (tally_) tally_->Sample(model, data, motors);
    last_time_ = data->time;
  }

  void Happened(double t, const std::string& what) override {
    if (tally_) tally_->Event(t, what);
  }

  // After the bridge returned: stops the client (when it still runs) and writes the result.
  RehearsalResult Finish(const BridgeStats& stats) {
    Join();
    if (start_error_) std::rethrow_exception(start_error_);
    RehearsalResult r;
    r.bridge = stats;
    r.client = Ending(stats);
    if (watch_) {
      r.view = watch_->View(client_ ? client_start_ : NAN);
      r.rows = tally_->Rows();
      r.rows.push_back(internal::ClientProcessRow(r.client, spec_.config));
      std::vector<CheckRow> client_rows = watch_->Rows(r.view, stats);
      r.rows.insert(r.rows.end(), client_rows.begin(), client_rows.end());
      r.trace = tally_->TakeTrace();
    } else {
      r.rows.push_back(internal::ClientProcessRow(r.client, spec_.config));
    }
    for (CheckRow& row : internal::BridgeRows(stats, spec_.config)) r.rows.push_back(row);
    return r;
  }

 private:
  ClientEnding Ending(const BridgeStats& stats) {
    ClientEnding e;
    if (!client_) {
      e.kind = ClientEnding::Kind::kNotStarted;
      e.text = "not started: the bridge stopped before it was up";
      return e;
    }
    if (ended_early_) {
      e.kind = ClientEnding::Kind::kExitedEarly;
      e.time = ended_time_;
    } else {
      e.time = stats.time;
      bool killed = client_->Stop(SIGINT, spec_.client.grace);
      e.kind = killed ? ClientEnding::Kind::kKilled : ClientEnding::Kind::kStopped;
      if (never_commanded_) e.time = stats.time;
    }
    e.exit_code = client_->exit_code();
    e.signal = client_->signal();
    e.wall = client_->wall();
    e.last_lines = client_->Tail();
    e.text = client_->HowItEnded();
    return e;
  }

  const RehearsalSpec& spec_;
  StopToken caller_;
  StopSource bridge_stop_;
  std::thread watcher_;
  std::atomic<bool> finished_{false}, started_{false}, commanded_{false}, ended_early_{false};
  bool never_commanded_ = false;  // written by the watcher, read after Join
  std::atomic<double> last_time_{0};
  double ended_time_ = NAN;
  double client_start_ = NAN;
  std::exception_ptr start_error_;
  std::unique_ptr<internal::ClientProcess> client_;
  std::unique_ptr<internal::ClientWatch> watch_;
  std::unique_ptr<internal::RehearsalTally> tally_;
};

}  // namespace

bool RehearsalResult::passed() const {
  return !bridge.diverged && CountUnaccepted(rows, CheckStatus::kFail) == 0;
}

RehearsalResult Rehearse(const Model& model, const std::vector<Assignment>& start,
                         const RehearsalSpec& spec, const StopToken& stop,
                         const BridgeNotice& notice, Notices* notices) {
  if (spec.client.command.find_first_not_of(" \t\n") == std::string::npos) {
    throw ArgumentError("client", Quoted(spec.client.command),
                        "must be a command line to run against the bridge (a deploy script "
                        "and its arguments)");
  }
  if (!std::isfinite(spec.config.until) || spec.config.until < 0) {
    throw ArgumentError("until", std::to_string(spec.config.until),
                        "a rehearsal needs a finite length: a simulated time in seconds at "
                        "which the client is stopped and the verdict given");
  }
  Rehearsal rehearsal(spec, stop);
  rehearsal.Watch();
  BridgeStats stats;
  try {
    stats = RunBridge(model, start, spec.config, rehearsal.bridge_token(), notice, &rehearsal);
  } catch (...) {
    rehearsal.Join();
    throw;  // the client, if started, is killed with the rehearsal
  }
  RehearsalResult result = rehearsal.Finish(stats);
  if (stop.stop_requested()) {
    AddTo(notices, {NoticeLevel::kWarning, NoticeTopic::kOther, "rehearsal",
                    fmt::format("stopped at t = {:.3f} s, before its end at {:g} s: the verdict "
                                "covers what ran",
                                stats.time, spec.config.until)});
  }
  return result;
}

}  // namespace plumb
