// plumb bridge: the model as virtual hardware over DDS, wire-compatible with Unitree SDK2.
//
// The bridge subscribes to rt/lowcmd and publishes rt/lowstate with Unitree's own message
// types (unitree_go: Go2, B2, H1, 20 motors; unitree_hg: G1, H1-2, 35 motors) and CRC, so
// a controller written with Unitree's SDK drives the simulation as it drives the robot. At
// every physics step each motor applies tau = tau_ff + kp (q_des - q) + kd (dq_des - dq)
// from the latest command (mode 0: no torque), inside the step loop: nothing races it.
//
// Modes: lockstep advances one control period per command received (deterministic, as fast
// as the controller, for CI): commands that arrive together wait in a bounded queue and are
// applied in order, one period each. Realtime is paced to the wall clock and publishes at the
// configured rate; the latest command is the one in force, as on the robot. When no command
// arrives for the watchdog's timeout the motors go to damping (kp = 0, kd as configured) until
// commands return; in lockstep the simulation then goes on in real time, as a robot would.
// Realtime damps too before the first command arrives (not a watchdog trip: nothing was
// controlling the robot yet).
//
// Thread-safety: RunBridge blocks the calling thread, which steps a copy of `model` (only read);
// CycloneDDS runs threads of its own for the link. `stop` may be asked from any thread or a
// signal handler. LoadBridgeConfig keeps no state. Bridges on one DDS domain id (in one process
// or several) share rt/lowcmd and rt/lowstate: run one per domain.

#ifndef PLUMB_INCLUDE_PLUMB_BRIDGE_H_
#define PLUMB_INCLUDE_PLUMB_BRIDGE_H_

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <map>
#include <string>
#include <vector>

#include "plumb/model.h"
#include "plumb/notice.h"
#include "plumb/path.h"
#include "plumb/stop.h"

namespace plumb {

enum class BridgeFamily { kGo, kHg };
enum class BridgeMode { kLockstep, kRealtime };

// One injected fault (see src/bridge/faults.h for what each does). Times are simulated.
struct FaultSpec {
  enum class Kind {
    kLatency,
    kDrop,
    kNoise,
    kTorqueLimit,
    kMotorFailure,
    kImuFreeze,
    kControllerPause
  };
  Kind kind = Kind::kLatency;
  bool state = false;  // latency, drop: the state direction (else commands)
  double start = 0;    // s of simulated time
  double stop = INFINITY;
  double fixed = 0, jitter = 0;  // latency, s
  double probability = 0;        // drop
  std::string signal;            // noise: q, dq, tau_est, gyro, accel, quat
  double sigma = 0, bias = 0;    // noise
  int motor = -1;                // noise, torque_limit, motor_failure (required): -1 all
  double limit = INFINITY;       // torque_limit, N*m
  bool stuck = false;            // motor_failure: hold position instead of zero torque
  std::string text;              // as the log names it: "drop of commands (p = 0.2)"
};

// Where the published IMU comes from ([imu] table). Empty: the sensor named imu_quat / imu_gyro /
// imu_acc (unitree_mujoco's names), else the first framequat / gyro / accelerometer sensor of the
// model, else the base body (the first body moved by a free joint).
struct BridgeImuSource {
  std::string quaternion;     // a framequat sensor's name
  std::string gyroscope;      // a gyro sensor's name
  std::string accelerometer;  // an accelerometer sensor's name
  std::string body;           // the body read where no sensor is named or found
};

// What rt/sportmodestate (unitree_go SportModeState_) reports ([sport_state] table): the base
// body's position and velocity, its height above the feet, and each foot's position, velocity
// and contact force. Published at the state rate when the model has a base body (or one is
// named); faults on the state (latency, drop) and noise on position, velocity and foot_force
// apply to it as to rt/lowstate.
struct BridgeSportState {
  bool publish = true;
  std::string base;  // a body; empty: the first body moved by a free joint
  // Up to 4 feet in the message's order (Unitree's quadrupeds: FR, FL, RR, RL), each a site,
  // geom or body (looked up in that order); empty: the foot fields stay zero.
  std::vector<std::string> feet;
};

// The elastic band ([band] table): a spring-damper from a fixed anchor to a body that holds a
// robot up until it is released, as robots are started on a gantry. The force acts along the
// line from the body's centre of mass to the anchor: stiffness (stretch beyond `length`) and
// damping (the speed along the line); a slack band (shorter than `length`) pulls nothing.
struct BridgeBand {
  std::string body;  // empty: no band
  // world frame, m; NaN: 1 m straight above the body's centre of mass at the start
  double anchor[3] = {NAN, NAN, NAN};
  double stiffness = 1000;  // N/m
  double damping = 200;     // N*s/m
  // rest length, m; NaN: the length at which the band holds the robot's whole weight with the
  // body at its start position (the robot hangs where it starts)
  double length = NAN;
  double release_at = INFINITY;  // s of simulated time
  std::string release_button;    // a gamepad button (R1, L1, start, ..., A, B, X, Y, ...)
  // A hoist holds a robot upright, not only up: a rotational spring-damper keeps the body at
  // its start orientation. N*m/rad; NaN: ten times the robot's weight times 1 m, at most what
  // one explicit step of the body alone takes (I / (2 dt)^2, I its least principal inertia);
  // 0: no hold (the robot hangs as a pendulum, tilted until its centre of mass is under the
  // band's line).
  double hold_stiffness = NAN;
  // N*m*s/rad; NaN: critical for hold_stiffness and the robot's inertia about the body, at
  // most I / (2 dt).
  double hold_damping = NAN;
};

// The wireless gamepad ([gamepad] table, --gamepad): rt/wirelesscontroller and
// rt/wireless_controller (unitree_go WirelessController_), and the 40-byte wireless_remote field
// of rt/lowstate, fed from a file of timed events (src/bridge/gamepad_script.h:
// "t = 2.0: start; t = 3.0: lx = 0.5 for 1.0 s").
struct BridgeGamepad {
  std::string events;  // the events file; empty: no gamepad
  double rate = 100;   // messages per second of simulated time
  // Unitree's robots and SDK examples read rt/wirelesscontroller; unitree_mujoco's C++
  // simulator publishes rt/wireless_controller. Both go out unless `topics` says otherwise.
  std::vector<std::string> topics = {"rt/wirelesscontroller", "rt/wireless_controller"};
};

// Where each name the model must have was written in the configuration file, so that a name
// the model lacks is reported at its line: "motors[2]", "imu.body", "secondary_imu.gyroscope",
// "band.body", "sport_state.feet[0]", ... -> "FILE:LINE:COLUMN". Empty for a configuration
// built in code.
using BridgePositions = std::map<std::string, std::string>;

struct BridgeConfig {
  BridgeFamily family = BridgeFamily::kGo;
  BridgeMode mode = BridgeMode::kLockstep;
  std::uint32_t domain = 1;       // DDS domain id (0..232)
  double control_period = 0.002;  // s: simulated time per command (lockstep), per state (realtime)
  // The tick of the first state, ms; later states add their simulated time. A real robot's
  // tick counts from its boot and is never 0 (scripts wait for a nonzero one).
  std::uint32_t start_tick = 1000;
  // hg: the robot type LowState_ reports (scripts echo it in LowCmd_). -1: from the motor
  // count, as Unitree's G1 rev 1.0 reports it: 5 for 29 motors, 4 for 23; else 0, said at start.
  int mode_machine = -1;
  // The motors in slot order (motor_cmd[i], motor_state[i]): actuator or joint names; empty:
  // every actuator in order. A "" entry is an empty slot: the robot has it, the model no motor
  // for it (Unitree's H1 policy leaves the torso's slot 6 out); its state is all zero and its
  // commands drive nothing.
  std::vector<std::string> motors;
  bool check_crc = true;  // drop (and count) commands whose CRC is wrong
  // s without a good command before damping: of wall time in realtime; of simulated time in
  // lockstep (periods answered by lost, bad or paused commands), where a controller that is
  // merely late stops simulated time instead (watchdog_patience)
  double watchdog_timeout = 0.1;
  double watchdog_kd = 1.0;  // N*m*s/rad of damping while the watchdog holds
  // lockstep: s of wall time a late controller may take for a command (a policy's first call
  // loading its weights) while simulated time waits; past it the controller counts as gone:
  // the watchdog damps and time runs on at wall-clock pace until a command comes
  double watchdog_patience = 10;
  std::string log;          // the flight recorder's CSV file; empty: none
  double until = INFINITY;  // stop after this much simulated time, s
  std::string source;       // where the configuration came from, for messages
  BridgeImuSource imu;      // [imu] table
  // [secondary_imu] table: rt/secondary_imu (the family's IMUState_), where the robot has a
  // second IMU (the G1's torso). Published when the table is present or the model has sensors
  // named secondary_imu_quat / _gyro / _acc (unitree_mujoco's names).
  BridgeImuSource secondary_imu;
  bool secondary_imu_configured = false;
  BridgeSportState sport_state;   // [sport_state] table
  BridgeBand band;                // [band] table
  BridgeGamepad gamepad;          // [gamepad] table
  std::vector<FaultSpec> faults;  // [[faults]] tables
  std::uint64_t seed = 0;         // of every random draw of the faults
  // lockstep: commands that may wait for their period; beyond it the oldest is dropped
  std::size_t command_queue = 64;
  BridgePositions positions;  // filled by LoadBridgeConfig
};

// Reads a bridge configuration (TOML). Keys: family = "go" | "hg", mode = "lockstep" |
// "realtime", domain, control_period, start_tick, mode_machine (hg only), motors = [names, ""],
// check_crc, log, until, seed,
// command_queue, a [watchdog] table with timeout_ms, kd and patience_s, [imu] and [secondary_imu]
// tables with quaternion, gyroscope, accelerometer (sensor names) and body, a [sport_state] table
// with publish, base and feet, a [band] table with body, anchor = [x, y, z], stiffness, damping,
// length, release_at and release_button, a [gamepad] table with events (a file, relative to
// the configuration's folder; RunBridge reads it), rate and topics, and [[faults]] tables.
// The file is read as ReadInputFile reads it (src/core/input_file.h): a FIFO, a directory or a
// device is refused, and so is a file over 1 MiB.
// @throws ValueError naming the file, line and key for anything unknown or out of range, or a
// motor named twice, or motors = [...] of empty slots only; IoError when the file is missing, not
// a regular file, or too large.
BridgeConfig LoadBridgeConfig(const std::string& path);

struct BridgeStats {
  long commands = 0;          // applied
  long bad_crc = 0;           // dropped: CRC mismatch
  long non_finite = 0;        // dropped: NaN or infinite target or gain
  long states = 0;            // published
  long watchdog_trips = 0;    // times the watchdog went to damping
  long dropped_commands = 0;  // lost to an injected drop
  long dropped_states = 0;
  long paused_commands = 0;  // ignored during an injected controller pause
  // dropped: from another controller while the one in charge is alive (see RunBridge)
  long foreign_commands = 0;
  // lockstep: dropped from a full command queue (the oldest waiting, see command_queue)
  long queue_drops = 0;
  long steps = 0;
  long sport_states = 0;  // rt/sportmodestate published (lost to a fault included)
  long secondary_imu_states = 0;
  long gamepad_messages = 0;   // rt/wirelesscontroller messages (each topic's copy counts once)
  double band_released = NAN;  // simulated time the band let go, s (NaN: it did not, or none)
  double time = 0;             // simulated time at the end, s
  // Simulated time over wall-clock time from the first period (lockstep: the first command)
  // to the end: 1 keeps up with the wall clock; NaN when no period ran.
  double realtime_factor = NAN;
  // Paced periods (realtime, and lockstep while its controller is gone) that started more than
  // one period after they were due: the simulation fell behind the wall clock by that much.
  long late_periods = 0;
  double worst_lateness = 0;  // s after it was due, of the latest period (0: none late)
  // lockstep: waits for a command longer than watchdog_timeout of wall time (simulated time
  // stopped meanwhile), and the longest wait for one after the first command, s
  long late_commands = 0;
  double longest_wait = 0;
  bool diverged = false;  // the run stopped because the state went bad
  std::string problem;    // what went bad, when it did
};

// One motor slot of a command as the client sent it (rt/lowcmd's motor_cmd[i]), before the
// bridge maps it onto the model: slots beyond the model's motors included.
struct BridgeCommandSlot {
  int mode = 0;
  double q = 0, dq = 0, tau = 0, kp = 0, kd = 0;
};

// A motor of the model as the bridge drives it: its name (actuator or joint), the joint it
// moves, and the torque it can give, N*m (from forcerange and ctrlrange x gain x gear). An
// empty slot ("" in motors = [...]) has no name and no joint.
struct BridgeMotorInfo {
  std::string name;
  int joint = -1;
  int actuator = -1;  // -1: a joint driven through qfrc_applied
  double torque_lo = -INFINITY, torque_hi = INFINITY;
  bool empty() const { return joint < 0; }
};

// One motor at a published state: what it measured, the command in force, and the torque the
// law asked for before the limits clipped it (what it applied is clipped to torque_lo/hi).
struct BridgeMotorSample {
  double q = 0, dq = 0;
  BridgeCommandSlot command;  // in force (mode 0 before the first command)
  double torque = 0;          // kp (q_des - q) + kd (dq_des - dq) + tau, unclipped, N*m
  bool damping = false;       // the watchdog (or the wait for a controller) damps instead
};

// What a caller watches while the bridge runs (a rehearsal: plumb/rehearse.h). Called on
// RunBridge's thread; a slow observer slows the bridge.
class BridgeObserver {
 public:
  virtual ~BridgeObserver() = default;
  // The link is up and the first state has gone out: a client may start now. `model` is the
  // bridge's copy; `motors` in slot order, empty slots included (BridgeMotorInfo::empty); the
  // samples of Published are in the same order, an empty slot's all zero.
  virtual void Started(const Model& /*model*/, const std::vector<BridgeMotorInfo>& /*motors*/) {}
  // A good command (CRC and values checked) from the controller in charge arrived, at
  // simulated time `t` and `wall` s of the steady clock: every slot of the message.
  virtual void Commanded(double /*t*/, double /*wall*/,
                         const std::vector<BridgeCommandSlot>& /*slots*/) {}
  // A state at simulated time data->time went out (or was lost to a fault), its derived
  // quantities computed: the model's data and each motor.
  virtual void Published(const Model& /*model*/, const Data& /*data*/,
                         const std::vector<BridgeMotorSample>& /*motors*/) {}
  // Something the flight log records (a fault beginning, the watchdog, a gamepad event, the
  // band's release), at simulated time `t`.
  virtual void Happened(double /*t*/, const std::string& /*what*/) {}
};

// The CycloneDDS configuration (XML) of the bridge's domain: loopback only (`lo`), no
// multicast, peers found at 127.0.0.1. A rehearsal gives it to its client as CYCLONEDDS_URI,
// for a client that starts DDS without naming an interface.
std::string BridgeLoopbackConfig();

// What a run did, in one paragraph: "12.5 s simulated in 6250 steps; 6250 commands applied,
// 0 dropped for a bad CRC, ...; realtime factor 0.983, 12 late periods (the worst 33.1 ms
// late)", and the log's file when there is one.
std::string BridgeSummary(const BridgeStats& stats, const BridgeConfig& config);

// What the user should hear while the bridge runs: a note such as "lockstep: waiting for the
// first command on rt/lowcmd" (once), or a warning that a lockstep controller is late or that
// realtime pacing falls behind the wall clock (at most one every 5 s). Subject "bridge", topic
// kOther. Called on RunBridge's thread; the flight recorder logs them too.
using BridgeNotice = std::function<void(const Notice&)>;

// Runs the bridge until config.until, `stop` asking (it returns then, without throwing), or
// the state going bad (stats.diverged). Starts from `start`. `notice` (may be empty) hears
// what the user should know while it runs.
// One controller at a time drives the robot: the DataWriter whose good command (CRC and
// values checked) arrives first is in charge; commands from any other writer are dropped,
// counted (foreign_commands) and logged once per writer, and do not advance a lockstep
// period. When the controller in charge has been silent for the watchdog timeout, the next
// writer with a good command takes over, and the log says so.
// @throws ValueError for a configuration that does not fit the model (unknown motor or IMU
// sensor, more motors than the family has, a control_period that is not a whole number of
// timesteps) or a domain id above 232; ArgumentError (argument "until") for a config.until that
// is negative or NaN, as LoadBridgeConfig refuses it in a file; ValueError / PathError when the
// model refuses `start`;
// UnavailableError when DDS cannot start or fails; IoError when config.log cannot be written;
// MujocoError.
// `observer` (may be null) watches the run.
BridgeStats RunBridge(const Model& model, const std::vector<Assignment>& start,
                      const BridgeConfig& config, const StopToken& stop,
                      const BridgeNotice& notice = {}, BridgeObserver* observer = nullptr);

}  // namespace plumb

#endif  // PLUMB_INCLUDE_PLUMB_BRIDGE_H_
