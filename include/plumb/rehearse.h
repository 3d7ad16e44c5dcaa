// plumb bridge --client: a deployment rehearsal. The bridge (plumb/bridge.h) runs the model as
// the robot; the client, the command that will drive the real robot (a vendor's deploy script
// with its trained policy, unmodified), runs against it as its own process; at the end the
// rehearsal says whether it held: the user's assertions over time windows, what plumb saw of
// the client (the command period it kept, targets outside the joints' ranges, gains that ask
// more torque than the motors have, motors the model lacks, actuators of the model that add a
// PD of their own), and how the client ended.
//
// Example:
//   plumb::RehearsalSpec spec;
//   spec.config = plumb::LoadBridgeConfig("go2-bridge.toml");
//   spec.config.until = 10;
//   spec.client.command = "python3 deploy.py --domain {domain}";
//   spec.assertions.push_back(
//       plumb::ParseRehearsalAssertion(model, spec.config, "xpos[base][2] > 0.2"));
//   plumb::RehearsalResult r = plumb::Rehearse(model, {}, spec, stop.token());
//   r.passed()  // no FAIL row
//
// Thread-safety: Rehearse blocks the calling thread, which runs the bridge; it starts the
// client once the bridge is up, and watches it from a thread of its own. Rehearsals on one DDS
// domain share its topics: run one per domain.

#ifndef PLUMB_INCLUDE_PLUMB_REHEARSE_H_
#define PLUMB_INCLUDE_PLUMB_REHEARSE_H_

#include <cmath>
#include <cstddef>
#include <string>
#include <utility>
#include <vector>

#include "plumb/bridge.h"
#include "plumb/check.h"
#include "plumb/model.h"
#include "plumb/notice.h"
#include "plumb/path.h"
#include "plumb/scenario.h"
#include "plumb/stop.h"

namespace plumb {

// The client: a command line run by /bin/sh -c, in its own process group.
struct RehearsalClient {
  // "{domain}" in it is replaced by the bridge's DDS domain id; the client's environment has
  // PLUMB_BRIDGE_DOMAIN set to it as well.
  std::string command;
  std::string directory;  // its working directory; empty: plumb's
  std::vector<std::pair<std::string, std::string>> environment;  // set on top of plumb's
  // s of wall time from its start for its first command; past it the client "never sent a
  // command" and the rehearsal ends (loading a policy takes seconds)
  double first_command_timeout = 60;
  // At the end: SIGINT (as Ctrl-C), then SIGKILL to its process group after `grace` s.
  double grace = 5;
  std::size_t tail_lines = 20;  // of its output (stdout and stderr), kept for the report
  std::string output;           // a file for its whole output; empty: none
};

// An assertion of a rehearsal: on the model's paths (plumb's scenario language), or on a
// signal of the bridge's motors.
struct RehearsalAssertion {
  enum class Signal {
    kPath,           // assertion.paths
    kTrackingError,  // q_des - q, rad (m), while a command is in force
    kTorque,         // what the law asks, N*m, unclipped
    kSaturated,      // 1 when that is beyond the motor's limit, else 0
  };
  Assertion assertion;  // its paths are empty for a motor signal
  Signal signal = Signal::kPath;
  std::vector<int> motors;         // a motor signal's motors, in motor order
  std::vector<std::string> names;  // and how each reads: "tracking_error[FR_hip]"
};

struct RehearsalSpec {
  BridgeConfig config;  // config.until must be finite: the rehearsal's length, s simulated
  RehearsalClient client;
  std::vector<RehearsalAssertion> assertions;  // ParseRehearsalAssertion
};

// How the client ended.
struct ClientEnding {
  enum class Kind {
    kStopped,      // it ended on plumb's signal at the end of the rehearsal
    kKilled,       // it ignored the signal for `grace` s: killed
    kExitedEarly,  // it ended before the rehearsal did
    kNotStarted,   // the bridge did not come up, or it could not be started
  };
  Kind kind = Kind::kNotStarted;
  int exit_code = -1;  // when it exited (else -1)
  int signal = 0;      // the signal that ended it (else 0)
  double time = NAN;   // simulated time when it ended or was stopped, s
  double wall = NAN;   // s of wall time it ran
  std::vector<std::string> last_lines;  // its output's last lines
  std::string text;  // "exited with status 1 at t = 0.42 s", "ended on SIGINT", ...
};

// "stopped", "killed", "exited early", "not started".
const char* ClientEndingName(ClientEnding::Kind kind);

// The commands plumb received from the client, whatever the client's own configuration says.
struct ClientMotorView {
  std::string name;  // the motor (actuator or joint)
  long commands = 0;
  // commanded positions outside the joint's range (limited joints), and the worst, rad or m
  long outside_range = 0;
  double worst_outside = 0;  // by how much
  // states where the law asked for more torque than the motor has (kp * error beyond it)
  long saturated = 0;
  double saturated_fraction = 0;  // of the states after the first command
  double worst_torque = 0;        // the largest |torque| asked, N*m
  double tracking_rms = NAN;      // q_des - q over the states after the first command, rad
  double tracking_worst = 0;
};

struct ClientView {
  long commands = 0;               // good commands from the controller in charge
  double first_command = NAN;      // s of wall time from the client's start to its first
  double first_command_time = NAN;  // simulated time of the first command, s
  // wall time between successive commands, s (NaN with fewer than two)
  double period_median = NAN, period_p95 = NAN, period_worst = NAN;
  double commands_per_period = NAN;  // commands per control_period of simulated time
  // the model's motors in slot order (a slot empty in motors = [...] left out)
  std::vector<ClientMotorView> motors;
  // Slots beyond the model's motors, or empty in the bridge's motors = [...], that the client
  // asked torque of (kp, kd or tau not zero): "slot 12 (mode 1, kp 20)", "slot 6 (empty in
  // motors = [...]) (mode 1, kp 20)".
  std::vector<std::string> unknown_motors;
  // Actuators of the model that act on a motor's joint with a PD of their own (a position or
  // velocity servo, a bias) on top of the commanded one: "actuator 'FR_hip_pos' on joint
  // 'FR_hip_joint' (kp 50)".
  std::vector<std::string> own_pd;
};

// One sample of the rehearsal's time axis, for the report: at each published state the
// asserted signals, and each motor's commanded and measured position.
struct RehearsalTrace {
  std::vector<std::string> signals;  // names of the asserted paths, then "q_des[m]", "q[m]"
  std::vector<double> time;          // s simulated
  std::vector<std::vector<double>> values;  // [signal][sample]
  std::vector<std::pair<double, std::string>> events;  // faults, watchdog, gamepad, band
};

struct RehearsalResult {
  BridgeStats bridge;
  ClientEnding client;
  ClientView view;
  // The verdict: one row per assertion (section "assert"), the client's rows (section
  // "client": client.process, client.commands, client.period, client.range, client.torque,
  // client.motors, client.own_pd, client.flood), and the bridge's (section "bridge":
  // bridge.crc, bridge.watchdog, bridge.diverged).
  std::vector<CheckRow> rows;
  RehearsalTrace trace;
  bool passed() const;  // no FAIL row, and the bridge did not diverge
};

// Parses an assertion of a rehearsal: plumb's scenario language (plumb/scenario.h:
// "xpos[pelvis][2] > 0.5", "mean(qvel[0]) > 0.3 during [7, 11]") over the model's paths, and
// the motors' signals: tracking_error[MOTOR] (q_des - q, rad), torque[MOTOR] (what the law
// asks, N*m), saturated[MOTOR] (1 when that is beyond the motor's limit, else 0; mean(...) is
// the fraction of states). MOTOR is a name of the bridge's motors, a motor number (its slot:
// motor_cmd[MOTOR], counting empty slots of motors = [...], which no assertion may name), or
// '*' (every motor, empty slots left out).
// @throws ValueError / PathError quoting it.
RehearsalAssertion ParseRehearsalAssertion(const Model& model, const BridgeConfig& config,
                                           const std::string& text);

// Runs the rehearsal: the bridge from `start` until spec.config.until (or `stop`, or the
// client ending early or never commanding), the client started once the bridge is up and
// stopped at the end. `notice` hears the bridge's sentences while it runs; `notices` (may be
// null) what the rehearsal has to say about itself (stopped before its end).
// @throws as RunBridge does; ArgumentError for an empty command or an infinite until;
// ValueError naming the directory when the client's working directory is not one; IoError
// when the client cannot be started or its output file cannot be written.
RehearsalResult Rehearse(const Model& model, const std::vector<Assignment>& start,
                         const RehearsalSpec& spec, const StopToken& stop,
                         const BridgeNotice& notice = {}, Notices* notices = nullptr);

}  // namespace plumb

#endif  // PLUMB_INCLUDE_PLUMB_REHEARSE_H_
