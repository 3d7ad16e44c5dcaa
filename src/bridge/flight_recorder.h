// The bridge's flight recorder: every state published, every command taken and every event
// (fault started or stopped, watchdog, command dropped), one CSV row each, in time order.
//
// Columns: time, kind (state, command or event), event (its text, or what happened to a
// state: "dropped (fault)", "held (latency)"), then plumb paths (so `plumb replay` and
// `identify` read it like a `plumb run --format csv` log): qpos[...] and qvel[...] (every
// element), ctrl[actuator] for each motor that is an actuator and qfrc_applied[dof] for each
// that is a joint (what was applied), sensordata[...] (every element); then, per motor i,
// what crossed the link: cmd.mode[i], cmd.q[i], cmd.dq[i], cmd.kp[i], cmd.kd[i], cmd.tau[i]
// (command rows) and state.q[i], state.dq[i], state.tau_est[i] (state rows, as published,
// noise included). Cells a row does not concern are empty. Written through AtomicFile: the
// log appears complete when the bridge stops, or not at all.

#ifndef PLUMB_SRC_BRIDGE_FLIGHT_RECORDER_H_
#define PLUMB_SRC_BRIDGE_FLIGHT_RECORDER_H_

#include <memory>
#include <string>
#include <vector>

#include "bridge/motor_map.h"
#include "bridge/pd_law.h"
#include "plumb/atomic_file.h"
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
  // Commits the file (until then it is a temporary file). @throws IoError.
  void Finish();

 private:
  void Line(const std::string& text);
  std::unique_ptr<AtomicFile> file_;
  const mjModel* m_;
  std::vector<int> ctrl_, applied_;  // actuator ids, dof ids
  std::size_t motors_ = 0;
  std::size_t simulated_ = 0;  // columns of the simulated state and what was applied
};

}  // namespace plumb::bridge

#endif  // PLUMB_SRC_BRIDGE_FLIGHT_RECORDER_H_
