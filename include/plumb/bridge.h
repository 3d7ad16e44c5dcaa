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
#include <string>
#include <vector>

#include "plumb/model.h"
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

// Where the published IMU comes from ([imu] table). Empty: the first framequat / gyro /
// accelerometer sensor of the model, else the base body (the first body moved by a free joint).
struct BridgeImuSource {
  std::string quaternion;     // a framequat sensor's name
  std::string gyroscope;      // a gyro sensor's name
  std::string accelerometer;  // an accelerometer sensor's name
  std::string body;           // the body read where no sensor is named or found
};

struct BridgeConfig {
  BridgeFamily family = BridgeFamily::kGo;
  BridgeMode mode = BridgeMode::kLockstep;
  std::uint32_t domain = 1;       // DDS domain id (0..232)
  double control_period = 0.002;  // s: simulated time per command (lockstep), per state (realtime)
  // The motors in motor order: actuator or joint names; empty: every actuator in order.
  std::vector<std::string> motors;
  bool check_crc = true;          // drop (and count) commands whose CRC is wrong
  double watchdog_timeout = 0.1;  // s of wall time without a command before damping
  double watchdog_kd = 1.0;       // N*m*s/rad of damping while the watchdog holds
  std::string log;                // the flight recorder's CSV file; empty: none
  double until = INFINITY;        // stop after this much simulated time, s
  std::string source;             // where the configuration came from, for messages
  BridgeImuSource imu;            // [imu] table
  std::vector<FaultSpec> faults;  // [[faults]] tables
  std::uint64_t seed = 0;         // of every random draw of the faults
  // lockstep: commands that may wait for their period; beyond it the oldest is dropped
  std::size_t command_queue = 64;
};

// Reads a bridge configuration (TOML). Keys: family = "go" | "hg", mode = "lockstep" |
// "realtime", domain, control_period, motors = [names], check_crc, log, until, seed,
// command_queue, a [watchdog] table with timeout_ms and kd, an [imu] table with quaternion,
// gyroscope, accelerometer (sensor names) and body, and [[faults]] tables. @throws ValueError
// naming the file, line and key for anything unknown or out of range.
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
  double time = 0;  // simulated time at the end, s
  // Simulated time over wall-clock time from the first period (lockstep: the first command)
  // to the end: 1 keeps up with the wall clock; NaN when no period ran.
  double realtime_factor = NAN;
  // Paced periods (realtime, and lockstep while the watchdog damps) that started more than
  // one period after they were due: the simulation fell behind the wall clock by that much.
  long late_periods = 0;
  double worst_lateness = 0;  // s after it was due, of the latest period (0: none late)
  bool diverged = false;      // the run stopped because the state went bad
  std::string problem;        // what went bad, when it did
};

// A sentence for the user while the bridge runs, such as "lockstep: waiting for the first
// command on rt/lowcmd" (once) or a warning that realtime pacing falls behind the wall clock
// (at most one every 5 s). Called on RunBridge's thread; the flight recorder logs them too.
using BridgeNotice = std::function<void(const std::string&)>;

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
// timesteps) or a domain id above 232; ValueError / PathError when the model refuses `start`;
// UnavailableError when DDS cannot start or fails; IoError when config.log cannot be written;
// MujocoError.
BridgeStats RunBridge(const Model& model, const std::vector<Assignment>& start,
                      const BridgeConfig& config, const StopToken& stop,
                      const BridgeNotice& notice = {});

}  // namespace plumb

#endif  // PLUMB_INCLUDE_PLUMB_BRIDGE_H_
