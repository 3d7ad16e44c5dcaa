// The bridge's flight recorder: every state published, every command taken and every event
// (fault started or stopped, watchdog, command dropped), one CSV row each, in time order.
//
// Columns: time, kind (state, command, event or gamepad), event (its text, what happened to a
// state: "dropped (fault)", "held (latency)", or the gamepad message published), then plumb paths
// named as `plumb run --format csv` names them (so `plumb replay` and `identify` read the log like
// its): qpos[joint] and qvel[joint] (every element: qpos[root][0..6] for a free joint; raw rows for
// an unnamed joint), ctrl[actuator] for each motor that is an actuator and qfrc_applied[joint] for
// each that is a joint (what was applied), sensordata[sensor] (every element); then, per motor in
// motor order, named by its actuator or joint (its slot number when unnamed), what crossed
// the link: cmd.mode[m], cmd.q[m], cmd.dq[m], cmd.kp[m], cmd.kd[m], cmd.tau[m] (command rows)
// and state.q[m], state.dq[m], state.tau_est[m] (state rows, as published, noise included).
// Cells a row does not concern are empty. An empty slot ("" in motors = [...]) has no columns.
//
// The log is append-only and survives the bridge being killed: it appears (through AtomicFile)
// with its header whole, then each row goes to the file as it happens, one write() of the whole
// line, with no buffer in between. A SIGKILL, a crash or an exception therefore leaves every
// row written before it, whole and in order. The one thing a kill can cut is the row being
// written at that instant: the kernel may stop a write() between two pages, so the last line
// can be cut short, and then has no newline (every whole line ends with one). Readers drop
// such a line (LoadRobotLog does, and says so). Finish() syncs the file to disk.

#ifndef PLUMB_SRC_BRIDGE_FLIGHT_RECORDER_H_
#define PLUMB_SRC_BRIDGE_FLIGHT_RECORDER_H_

#include <string>
#include <vector>

#include "bridge/motor_map.h"
#include "bridge/pd_law.h"
#include "plumb/model.h"

namespace plumb::bridge {

// A motor's values as published.
struct PublishedMotor {
  double q = 0, dq = 0, tau_est = 0;
};

class FlightRecorder {
 public:
  FlightRecorder(const std::string& path, const Model& model, const MotorMap& motors);
  // A state as published (`note`: empty, or what a fault did to it).
  void State(const mjData* d, const std::vector<PublishedMotor>& published,
             const std::string& note);
  void Command(double time, const std::vector<MotorCommand>& command);
  void Event(double time, const std::string& what);
  // A gamepad message as published ("lx 0.5 ly 0 rx 0 ry 0 keys 0x0004 (start)").
  void Gamepad(double time, const std::string& what);
  // Syncs the log to disk and closes it. @throws IoError.
  void Finish();
  ~FlightRecorder();
  FlightRecorder(const FlightRecorder&) = delete;
  FlightRecorder& operator=(const FlightRecorder&) = delete;

 private:
  // A row of `kind` whose event column says `what`.
  void Note(double time, const char* kind, const std::string& what);
  // Appends `text` and a newline with one write(). @throws IoError.
  void Line(const std::string& text);
  std::string path_;
  int fd_ = -1;  // the log, open for appending
  const mjModel* m_;
  std::vector<int> ctrl_, applied_;  // control rows, dof ids
  std::vector<std::size_t> slots_;   // the slots with a motor (not empty), in slot order
  std::size_t motors_ = 0;           // how many: slots_.size()
  std::size_t simulated_ = 0;        // columns of the simulated state and what was applied
};

}  // namespace plumb::bridge

#endif  // PLUMB_SRC_BRIDGE_FLIGHT_RECORDER_H_
