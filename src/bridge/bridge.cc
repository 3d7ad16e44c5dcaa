// The bridge loop (plumb/bridge.h): commands in, PD torques inside the step loop, state out.

#include "plumb/bridge.h"

#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <memory>
#include <optional>
#include <thread>

#include "bridge/band.h"
#include "bridge/command_check.h"
#include "bridge/command_queue.h"
#include "bridge/controllers.h"
#include "bridge/dds_link.h"
#include "bridge/faults.h"
#include "bridge/flight_recorder.h"
#include "bridge/gamepad_script.h"
#include "bridge/imu.h"
#include "bridge/messages.h"
#include "bridge/motor_map.h"
#include "bridge/pacer.h"
#include "bridge/pd_law.h"
#include "bridge/sport_state.h"
#include "bridge/unitree_crc.h"
#include "plumb/error.h"
#include "plumb/run.h"

namespace plumb {
namespace {

using Clock = std::chrono::steady_clock;

// A stuck motor: a stiff hold at the angle where it failed (N*m/rad, N*m*s/rad), clipped to
// the motor's limits like any other torque.
constexpr double kStuckStiffness = 1000, kStuckDamping = 20;

using bridge::Family;

template <BridgeFamily F>
class Loop {
 public:
  using Cmd = typename Family<F>::Cmd;
  using State = typename Family<F>::State;
  using ImuState = typename Family<F>::ImuState;
  using Outgoing = bridge::Outgoing<F>;
  using Link = bridge::Link<F>;

  Loop(const Model& model, const std::vector<Assignment>& start, const BridgeConfig& config,
       const BridgeNotice& notice, BridgeObserver* observer)
      : config_(config),
        notice_(notice),
        observer_(observer),
        work_(model.Clone()),
        data_(work_),
        // realtime takes the whole queue every period: only lockstep's is bounded
        queue_(config.mode == BridgeMode::kLockstep ? config.command_queue : SIZE_MAX),
        pacer_(config.control_period),
        faults_(config.faults, config.seed) {
    ApplyAssignments(work_, data_, start);
    data_.Forward();
    map_ = bridge::MotorMap::Bind(work_, config.motors, config.positions);
    if (map_.size() > static_cast<std::size_t>(Family<F>::kMotors)) {
      throw ValueError(fmt::format(
          "{}: {} motors, but a {} message carries {}: name at most that many in motors = [...]",
          config.source.empty() ? "the bridge" : config.source, map_.size(),
          F == BridgeFamily::kGo ? "unitree_go" : "unitree_hg", Family<F>::kMotors));
    }
    double dt = work_->opt.timestep;
    steps_per_period_ = std::lround(config.control_period / dt);
    if (steps_per_period_ < 1 ||
        std::fabs(steps_per_period_ * dt - config.control_period) > 1e-9 * config.control_period) {
      throw ValueError(fmt::format(
          "control_period {:g} s is not a whole number of the model's timesteps ({:g} s)",
          config.control_period, dt));
    }
    commands_.resize(map_.size());
    empty_slots_ = map_.EmptySlots();
    stuck_at_.assign(map_.size(), NAN);
    imu_ = bridge::Imu::Bind(work_, config.imu, bridge::kPrimaryImu, config.positions);
    secondary_ =
        bridge::Imu::Bind(work_, config.secondary_imu, bridge::kSecondaryImu, config.positions);
    if (config.secondary_imu_configured && !secondary_.reads()) {
      throw ValueError(
          fmt::format("{}: [secondary_imu] reads nothing: name its sensors (quaternion, gyroscope, "
                      "accelerometer) or its body",
                      config.source.empty() ? "the bridge" : config.source));
    }
    sport_ = bridge::SportState::Bind(work_, config.sport_state, config.positions);
    band_ = bridge::Band(work_.get(), data_.get(), config.band, config.positions);
    if (!config.gamepad.events.empty()) {
      pad_ = bridge::GamepadScript::Load(config.gamepad.events);
      pad_on_ = true;
    }
    if (!config.log.empty()) recorder_.emplace(config.log, work_, map_);
    mode_machine_ = ModeMachine();
    if (band_.on()) Event(band_.description());
  }

  BridgeStats Run(const StopToken& stop) {
    Link link(config_, sport_.enabled(), secondary_.reads());
    auto& commands = link.commands;
    Transitions();
    PublishPad(link);
    Publish(link);
    if (observer_) observer_->Started(work_, MotorInfo());
    controllers_.Start();
    bool lockstep = config_.mode == BridgeMode::kLockstep;
    // said once, at the start, whether or not a command is already there: the same words
    // every run, as a lockstep log repeats bit for bit
    if (lockstep) {
      Notice(NoticeLevel::kNote,
             "lockstep: waiting for the first command on rt/lowcmd; simulated time starts with it");
    }
    while (data_->time < config_.until - 0.5 * work_->opt.timestep && !stop.stop_requested()) {
      // lockstep: one period per command, when a state has gone out since the last command
      // (a state lost or still held back by an injected fault cannot be answered: time goes
      // on until a late one is released, then waits for its answer)
      // (a late controller stops simulated time; one gone past watchdog_patience does not)
      bool fresh = Drain(commands).fresh;
      bool wait = lockstep && !gone_ && awaiting_reply_ && queue_.empty();
      if (wait) fresh = AwaitCommand(link, stop) || fresh;
      bool took = TakeQueued();
      if (took) awaiting_reply_ = false;
      Watchdog(fresh);
      if (wait && !took && !gone_) continue;
      Pace(!lockstep || gone_);
      if (!StepPeriod()) break;
      Transitions();
      ReleaseHeldStates(link);
      PublishPad(link);
      Publish(link);
    }
    Summarize();
    if (recorder_) recorder_->Finish();
    stats_.time = data_->time;
    return stats_;
  }

 private:
  struct Arrival {
    bool fresh = false;  // a good command got through (the watchdog hears it)
  };
  struct Held {
    double at;  // simulated time it is released, s
    std::vector<bridge::MotorCommand> command;
    Outgoing state;
  };

  // The robot type an hg state reports: the configured one, else Unitree's G1 rev 1.0 value
  // for its motor count (unitree_ros' g1_description: 29 motors 5, 23 motors 4), else 0, said.
  int ModeMachine() {
    if (F != BridgeFamily::kHg || config_.mode_machine >= 0) return config_.mode_machine;
    if (map_.size() == 29) return 5;
    if (map_.size() == 23) return 4;
    Notice(
        NoticeLevel::kWarning,
        fmt::format("mode_machine: 0 in every state ({} motors is no G1 rev 1.0 that plumb "
                    "knows); set mode_machine in the configuration to the robot's type if "
                    "the client checks it",
                    map_.size()));
    return 0;
  }

  static Clock::duration Seconds(double s) {
    return std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(s));
  }

  // Takes every waiting command into the queue, each one period (lost ones too: the robot
  // drops them and goes on); a good one is applied when its period comes or, under injected
  // latency, when its time comes after that.
  Arrival Drain(bridge::DdsReader<Cmd>& reader) {
    Arrival a;
    Cmd cmd;
    double t = data_->time;
    dds_instance_handle_t writer = 0;
    while (reader.Take(&cmd, &writer)) {
      if (controllers_.Foreign(writer, &stats_.foreign_commands)) continue;
      if (faults_.ControllerPaused(t)) {
        ++stats_.paused_commands;
        Enqueue({});  // lockstep: the period passes without it, as for a lost command
        continue;
      }
      std::uint32_t n = command_count_++;
      if (faults_.DropCommand(t, n)) {
        ++stats_.dropped_commands;
        Enqueue({});
        continue;
      }
      std::vector<bridge::MotorCommand> next;
      bridge::CommandVerdict verdict =
          bridge::CheckCommand(cmd, config_.check_crc, map_.size(), &next, empty_slots_);
      if (verdict == bridge::CommandVerdict::kBadCrc) {
        ++stats_.bad_crc;
        Event(fmt::format("dropped a command with a bad CRC ({:#010x}, expected {:#010x})", cmd.crc,
                          bridge::UnitreeCrc(cmd)));
        Enqueue({});
        continue;
      }
      if (verdict == bridge::CommandVerdict::kNonFinite) {
        ++stats_.non_finite;
        Event("dropped a command with a NaN or infinite target or gain");
        Enqueue({});
        continue;
      }
      a.fresh = true;
      controllers_.Good(writer);
      if (observer_) {
        observer_->Commanded(t, std::chrono::duration<double>(Clock::now().time_since_epoch()).count(),
                             bridge::CommandSlots(cmd));
      }
      Enqueue({std::move(next), faults_.CommandLatency(t, n)});
    }
    if (a.fresh) last_good_time_ = t;
    return a;
  }

  // Queues a command for its period; a full (lockstep) queue drops its oldest, counted and
  // logged.
  void Enqueue(bridge::Arrived a) {
    if (queue_.Push(std::move(a))) return;
    ++stats_.queue_drops;
    Event(fmt::format(
        "lockstep: {} commands wait for their periods: dropped the oldest (the controller is "
        "ahead of the simulation)",
        queue_.capacity()));
  }

  // Takes what the coming period applies: lockstep the oldest waiting command, realtime every
  // one in order (the latest is in force). Returns whether there was one.
  bool TakeQueued() {
    bool took = !queue_.empty();
    do {
      if (queue_.empty()) break;
      bridge::Arrived a = queue_.Pop();
      if (a.command.empty()) continue;  // lost: the old command stays in force
      ++stats_.commands;
      if (recorder_) recorder_->Command(data_->time, a.command);
      if (a.delay > 0) {
        held_commands_.push_back({data_->time + a.delay, std::move(a.command), {}});
      } else {
        commands_ = std::move(a.command);
      }
    } while (config_.mode == BridgeMode::kRealtime);
    return took;
  }

  // Lockstep: waits for a command while simulated time stands still, for watchdog_patience
  // of wall time after the last one (before the first command there is no limit: a lockstep
  // run starts when its controller does, as Run says); past it the controller is gone. Before
  // the first command, and once the controller in charge has been silent for the watchdog's
  // timeout, the state goes out again every 50 ms, for a controller that joined late or takes
  // over. Returns whether a good command came.
  bool AwaitCommand(Link& link, const StopToken& stop) {
    bridge::DdsReader<Cmd>& commands = link.commands;
    auto began = Clock::now();
    auto deadline = controllers_.heard()
                        ? controllers_.last_good() + Seconds(config_.watchdog_patience)
                        : Clock::time_point::max();
    auto republish = began + std::chrono::milliseconds(50);
    bool fresh = false;
    bool late = false;
    while (queue_.empty() && !stop.stop_requested()) {
      if (Clock::now() >= deadline) {
        Gone();
        break;
      }
      if (controllers_.heard() && !late && controllers_.OwnerSilent()) {
        late = true;  // said on stderr, not logged: a lockstep log repeats bit for bit
        ++stats_.late_commands;
        Notice(NoticeLevel::kWarning,
               fmt::format("lockstep: the controller is late (no command for {:g} ms of wall "
                           "time at t = {:.3f} s): simulated time waits for it, up to {:g} s",
                           config_.watchdog_timeout * 1000, data_->time, config_.watchdog_patience),
               false);
      }
      auto until = std::min(deadline, republish);
      auto left = std::chrono::duration_cast<std::chrono::nanoseconds>(until - Clock::now());
      commands.Wait(
          std::max<dds_duration_t>(0, std::min<dds_duration_t>(left.count(), DDS_MSECS(50))));
      fresh = Drain(commands).fresh || fresh;
      // before the first command, and while the controller in charge is silent (for another
      // to take over): not before, as a controller that answers every state would answer a
      // copy too, and its extra command would take a period of its own
      if ((!controllers_.heard() || controllers_.OwnerSilent()) && queue_.empty() &&
          Clock::now() >= republish) {
        link.Write(last_state_);
        republish = Clock::now() + std::chrono::milliseconds(50);
      }
    }
    if (controllers_.heard()) {
      stats_.longest_wait = std::max(stats_.longest_wait,
                                     std::chrono::duration<double>(Clock::now() - began).count());
    }
    return fresh;
  }

  // Lockstep: the controller has not answered for watchdog_patience of wall time. The watchdog
  // damps, and time runs on at wall-clock pace until a command comes.
  void Gone() {
    gone_ = true;
    Event(
        fmt::format("lockstep: no command for {:g} s of wall time: the controller is gone; "
                    "simulated time runs on at wall-clock pace",
                    config_.watchdog_patience));
  }

  // Paces the coming period to the wall clock (when `paced`), counting late periods and
  // warning at most every 5 s while the simulation falls behind.
  void Pace(bool paced) {
    auto now = Clock::now();
    if (!started_) {
      started_ = true;
      wall_start_ = now;
      sim_start_ = data_->time;
    }
    if (!paced) {
      pacer_.Restart();  // a later spell of pacing starts from then, not late
      return;
    }
    std::this_thread::sleep_until(pacer_.due(now));
    now = Clock::now();
    double lateness = pacer_.Start(now);
    if (pacer_.Late(lateness) && now - last_warning_ >= std::chrono::seconds(5)) {
      last_warning_ = now;
      // (not logged in lockstep, whose log repeats bit for bit)
      Notice(NoticeLevel::kWarning,
             fmt::format("realtime: behind the wall clock: the period at t = {:.3f} s started "
                         "{:.1f} ms late ({} late so far; a loaded machine?)",
                         data_->time, lateness * 1000, pacer_.late_periods()),
             config_.mode == BridgeMode::kRealtime);
    }
  }

  // The run's realtime factor and late periods, in the stats and (realtime: a lockstep log
  // repeats bit for bit) the log.
  void Summarize() {
    stats_.late_periods = pacer_.late_periods();
    stats_.worst_lateness = pacer_.worst_lateness();
    if (!started_) return;
    double wall = std::chrono::duration<double>(Clock::now() - wall_start_).count();
    stats_.realtime_factor = wall > 0 ? (data_->time - sim_start_) / wall : NAN;
    if (config_.mode != BridgeMode::kRealtime) return;
    Event(fmt::format("realtime factor {:.3f} over {:.3g} s of wall time; {} late periods{}",
                      stats_.realtime_factor, wall, stats_.late_periods,
                      stats_.late_periods > 0
                          ? fmt::format(", the worst {:.1f} ms late", stats_.worst_lateness * 1000)
                          : ""));
  }

  // Tells the user (and the log, when `log`).
  void Notice(NoticeLevel level, const std::string& what, bool log = true) {
    if (notice_) notice_({level, NoticeTopic::kOther, "bridge", what});
    if (log) Event(what);
  }

  // Commands held back by latency whose time has come, in the order they arrived.
  void ApplyHeldCommands() {
    double t = data_->time;
    while (!held_commands_.empty() && held_commands_.front().at <= t + 1e-12) {
      commands_ = std::move(held_commands_.front().command);
      held_commands_.erase(held_commands_.begin());
    }
  }

  void ReleaseHeldStates(Link& link) {
    double t = data_->time;
    while (!held_states_.empty() && held_states_.front().at <= t + 1e-12) {
      link.Write(held_states_.front().state);
      last_state_ = held_states_.front().state;
      held_states_.erase(held_states_.begin());
      awaiting_reply_ = true;
    }
  }

  void Transitions() {
    for (const std::string& text : faults_.Transitions(data_->time)) Event(text);
  }

  // Damps when the controller falls silent (a watchdog trip) and, in realtime, before the
  // first command (not a trip: nothing was in control yet); resumes on a good command.
  // Silence is of wall time in realtime; in lockstep, of simulated time (periods answered by
  // lost, bad or paused commands), or a controller gone.
  void Watchdog(bool fresh) {
    bool realtime = config_.mode == BridgeMode::kRealtime;
    bool silent = realtime ? controllers_.OwnerSilent()
                           : gone_ || data_->time - last_good_time_ >
                                          config_.watchdog_timeout + 0.5 * work_->opt.timestep;
    if (!damping_ && !fresh && silent && (controllers_.heard() || realtime)) {
      damping_ = true;
      tripped_ = controllers_.heard();
      if (tripped_) {
        ++stats_.watchdog_trips;
        Event(fmt::format("watchdog: no command for {:g} ms: damping (kp = 0, kd = {:g})",
                          config_.watchdog_timeout * 1000, config_.watchdog_kd));
      } else {
        Event(fmt::format("no controller yet: damping (kp = 0, kd = {:g}) until the first command",
                          config_.watchdog_kd));
      }
    } else if (damping_ && fresh) {
      damping_ = false;
      gone_ = false;
      if (tripped_) Event("watchdog: commands are back: resuming");
    }
  }

  // False when the state went bad (stats_.diverged says what). Every step, the law reads the
  // motors (sensors included) at the state it acts on: mj_step1 computes the position and
  // velocity stages, the torques go in, mj_step2 finishes the step. RK4, which mj_step2 would
  // replace by Euler, takes a refresh of the derived arrays and a whole mj_step instead.
  bool StepPeriod() {
    mjData* d = data_.get();
    const mjModel* m = work_.get();
    bool rk4 = m->opt.integrator == mjINT_RK4;
    for (long k = 0; k < steps_per_period_; ++k) {
      if (rk4)
        refresh_(data_);
      else
        mj_step1(m, d);
      ApplyHeldCommands();
      PullBand();
      for (std::size_t i = 0; i < map_.size(); ++i) {
        double q = map_.Q(d, i), dq = map_.Dq(d, i);
        double tau = damping_ ? -config_.watchdog_kd * dq : bridge::PdTorque(commands_[i], q, dq);
        int failure = faults_.Failure(static_cast<int>(i), d->time);
        if (failure == 0) stuck_at_[i] = NAN;
        if (failure == 1) tau = 0;
        if (failure == 2) {
          // a stuck motor holds where it failed, as stiffly as its limits allow
          if (std::isnan(stuck_at_[i])) stuck_at_[i] = q;
          tau = kStuckStiffness * (stuck_at_[i] - q) - kStuckDamping * dq;
        }
        double limit = faults_.TorqueLimit(static_cast<int>(i), d->time);
        tau = std::clamp(tau, -limit, limit);
        map_.Apply(d, i, tau);
      }
      if (rk4)
        data_.Step();
      else
        mj_step2(m, d);
      ++stats_.steps;
      for (int i = 0; i < work_->nq + work_->nv; ++i) {
        double v = i < work_->nq ? d->qpos[i] : d->qvel[i - work_->nq];
        if (!std::isfinite(v) || d->warning[mjWARN_BADQACC].number > 0) {
          stats_.diverged = true;
          stats_.problem = fmt::format("the simulation diverged at t = {:.6g} s{}", d->time,
                                       d->warning[mjWARN_BADQACC].number > 0
                                           ? ": MuJoCo found a bad acceleration and reset the state"
                                           : "");
          Event(stats_.problem);
          return false;
        }
      }
    }
    return true;
  }

  void Publish(Link& link) {
    refresh_(data_);  // sensors, forces and the IMU of the state whose tick goes out
    Outgoing out;
    State& s = out.low;
    std::memset(&out, 0, sizeof out);
    Family<F>::Header(&s, mode_machine_);
    mjData* d = data_.get();
    double t = d->time;
    std::uint32_t n = state_count_++;
    std::vector<bridge::PublishedMotor> published(map_.size());
    for (std::size_t i = 0; i < map_.size(); ++i) {
      if (empty_slots_[i]) continue;  // all zero, as the memset left it
      auto& m = s.motor_state[i];
      int motor = static_cast<int>(i);
      m.mode = commands_[i].mode;
      m.q = static_cast<float>(map_.Q(d, i) + faults_.Noise("q", motor, t, n));
      m.dq = static_cast<float>(map_.Dq(d, i) + faults_.Noise("dq", motor, t, n));
      m.tau_est = static_cast<float>(map_.TauEst(d, i) + faults_.Noise("tau_est", motor, t, n));
      published[i] = {m.q, m.dq, m.tau_est};
    }
    if (!faults_.ImuFrozen(t) || !imu_read_) {
      imu_reading_ = imu_.Read(work_.get(), d);
      for (int k = 0; k < 4; ++k) imu_reading_.quaternion[k] += faults_.Noise("quat", k, t, n);
      for (int k = 0; k < 3; ++k) {
        imu_reading_.gyroscope[k] += faults_.Noise("gyro", k, t, n);
        imu_reading_.accelerometer[k] += faults_.Noise("accel", k, t, n);
      }
      imu_read_ = true;
    }
    bridge::FillImu(imu_reading_, &s.imu_state);
    if (pad_on_) bridge::PackWirelessRemote(pad_.At(t), s.wireless_remote);
    s.tick = config_.start_tick + static_cast<std::uint32_t>(std::llround(t * 1000));
    s.crc = bridge::UnitreeCrc(s);
    ++stats_.states;
    if (link.sport) {
      bridge::SportReading r = sport_.Read(work_.get(), d);
      for (int k = 0; k < 3; ++k) {
        r.position[k] += faults_.Noise("position", k, t, n);
        r.velocity[k] += faults_.Noise("velocity", k, t, n);
      }
      for (std::size_t i = 0; i < sport_.feet(); ++i) {
        r.foot_force[i] += faults_.Noise("foot_force", static_cast<int>(i), t, n);
      }
      out.sport = bridge::MakeSportMessage(t, r, imu_reading_, sport_.feet());
      ++stats_.sport_states;
    }
    if (link.imu) {
      bridge::FillImu(secondary_.Read(work_.get(), d), &out.imu);
      ++stats_.secondary_imu_states;
    }
    if (observer_) Observe();
    if (faults_.DropState(t, n)) {
      ++stats_.dropped_states;
      if (recorder_) recorder_->State(d, published, "dropped (fault)");
      return;
    }
    double delay = faults_.StateLatency(t, n);
    if (delay > 0) {
      held_states_.push_back({t + delay, {}, out});
      if (recorder_) recorder_->State(d, published, "held (latency)");
      return;
    }
    link.Write(out);
    last_state_ = out;
    awaiting_reply_ = true;
    if (recorder_) recorder_->State(d, published, "");
  }

  // The gamepad at its rate of simulated time (and at the start): every message on every
  // topic, and in the flight log; the script's events as they begin.
  void PublishPad(Link& link) {
    if (!pad_on_) return;
    double t = data_->time;
    for (const std::string& text : pad_.Begun(t)) Event(text);
    if (t < next_pad_ - 1e-9) return;
    bridge::GamepadState pad = pad_.At(t);
    bridge::PadMessage message = bridge::MakePadMessage(pad);
    for (auto& writer : link.pads) writer.Write(message);
    ++stats_.gamepad_messages;
    if (recorder_) recorder_->Gamepad(t, bridge::PadText(pad));
    double rate = config_.gamepad.rate;
    next_pad_ = (std::floor(t * rate + 1e-6) + 1) / rate;
  }

  // The band's pull for the coming step, or its release (logged) when its time or button
  // has come. `d`'s positions and velocities describe the step's start.
  void PullBand() {
    if (!band_.on()) return;
    mjData* d = data_.get();
    std::string released = band_.Release(d, pad_on_ ? pad_.At(d->time).keys : 0);
    if (!released.empty()) {
      stats_.band_released = d->time;
      Event(released);
      return;
    }
    band_.Apply(work_.get(), d);
  }

  void Event(const std::string& what) {
    if (recorder_) recorder_->Event(data_->time, what);
    if (observer_) observer_->Happened(data_->time, what);
  }

  std::vector<BridgeMotorInfo> MotorInfo() const {
    std::vector<BridgeMotorInfo> info;
    for (const bridge::Motor& m : map_.motors()) {
      info.push_back({m.name, m.joint, m.actuator, m.torque_lo, m.torque_hi});
    }
    return info;
  }

  // The state going out, for the observer: each motor, the command in force and the torque
  // the law asks for.
  void Observe() {
    const mjData* d = data_.get();
    std::vector<BridgeMotorSample> motors(map_.size());
    for (std::size_t i = 0; i < map_.size(); ++i) {
      const bridge::MotorCommand& c = commands_[i];
      BridgeMotorSample& s = motors[i];
      s.q = map_.Q(d, i);
      s.dq = map_.Dq(d, i);
      s.command = {c.mode, c.q, c.dq, c.tau, c.kp, c.kd};
      s.torque = bridge::PdTorque(c, s.q, s.dq);
      s.damping = damping_;
    }
    observer_->Published(work_, data_, motors);
  }

  const BridgeConfig& config_;
  const BridgeNotice& notice_;
  BridgeObserver* observer_;
  Model work_;
  Data data_;
  bridge::MotorMap map_;
  bridge::Imu imu_;
  DerivedRefresher refresh_{work_};
  long steps_per_period_ = 1;
  std::vector<bridge::MotorCommand> commands_;
  std::vector<bool> empty_slots_;  // "" in motors = [...]: published as zeros, driving nothing
  std::optional<bridge::FlightRecorder> recorder_;
  bool damping_ = false;
  int mode_machine_ = 0;        // hg: the robot type every state reports
  bool tripped_ = false;        // the damping is a watchdog trip (not the wait for a controller)
  bridge::CommandQueue queue_;  // commands waiting for their period
  bridge::Pacer pacer_;
  bool started_ = false;  // a period has run: wall_start_ and sim_start_ are set
  Clock::time_point wall_start_, last_warning_;
  double sim_start_ = 0;
  double last_good_time_ = 0;  // simulated time of the last good command, s
  bool gone_ = false;          // lockstep: no command for watchdog_patience: paced, damping
  bridge::Controllers controllers_{config_.watchdog_timeout,
                                   [this](const std::string& what) { Event(what); }};
  bool awaiting_reply_ = false;  // a state went out since the last command: lockstep waits
  bridge::Faults faults_;
  std::uint32_t command_count_ = 0, state_count_ = 0;  // the faults' message numbers
  std::vector<Held> held_commands_, held_states_;      // under injected latency
  std::vector<double> stuck_at_;                       // a stuck motor's position, or NaN
  bridge::ImuReading imu_reading_;                     // the last one (IMU freeze)
  bool imu_read_ = false;
  Outgoing last_state_{};  // what a late controller is sent
  bridge::SportState sport_;
  bridge::Imu secondary_;  // reads nothing: no rt/secondary_imu
  bridge::Band band_;
  bridge::GamepadScript pad_;
  bool pad_on_ = false;
  double next_pad_ = 0;  // simulated time of the next gamepad message
  BridgeStats stats_;
};

}  // namespace

BridgeStats RunBridge(const Model& model, const std::vector<Assignment>& start,
                      const BridgeConfig& config, const StopToken& stop,
                      const BridgeNotice& notice, BridgeObserver* observer) {
  // the rule LoadBridgeConfig applies to the file's until, for one set in code (--until)
  if (!(config.until >= 0)) {
    throw ArgumentError("until", fmt::format("{:g}", config.until),
                        "must be in [0, inf]: a simulated time in seconds to stop at (leave it "
                        "out to run until stopped)");
  }
  if (config.family == BridgeFamily::kGo) {
    return Loop<BridgeFamily::kGo>(model, start, config, notice, observer).Run(stop);
  }
  return Loop<BridgeFamily::kHg>(model, start, config, notice, observer).Run(stop);
}

}  // namespace plumb
