// The bridge's flight recorder: one CSV row per control period with the state and what was
// applied, under plumb paths (so `plumb replay` / `identify` read it like a `plumb run
// --format csv` log), and one row per event (command dropped, watchdog, fault) with the
// event's text in the `event` column and the numbers empty.
//
// Columns: time, event, qpos[...] (every element), qvel[...], ctrl[actuator] for each motor
// that is an actuator, qfrc_applied[dof] for each motor that is a joint, sensordata[...]
// (every element). Written through AtomicFile: the log appears complete when the bridge
// stops, or not at all.

#ifndef PLUMB_SRC_BRIDGE_FLIGHT_RECORDER_H_
#define PLUMB_SRC_BRIDGE_FLIGHT_RECORDER_H_

#include <memory>
#include <string>
#include <vector>

#include "bridge/motor_map.h"
#include "plumb/atomic_file.h"
#include "plumb/model.h"

namespace plumb::bridge {

class FlightRecorder {
 public:
  FlightRecorder(const std::string& path, const Model& model, const MotorMap& motors);
  void Row(const mjData* d);
  void Event(double time, const std::string& what);
  // Commits the file (until then it is a temporary file). @throws IoError.
  void Finish();

 private:
  std::unique_ptr<AtomicFile> file_;
  const mjModel* m_;
  std::vector<int> ctrl_, applied_;  // actuator ids, dof ids
  std::size_t columns_ = 0;
};

}  // namespace plumb::bridge

#endif  // PLUMB_SRC_BRIDGE_FLIGHT_RECORDER_H_
