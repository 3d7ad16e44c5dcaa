// Logs of a robot (or of plumb itself), as `plumb replay` and `plumb identify` take them.
//
// A log is a CSV file with a header row. It needs a `time` column (seconds, never going
// backwards; the steps may be irregular) and columns named by plumb paths:
//   - inputs that were applied: ctrl[...], qfrc_applied[...], xfrc_applied[...], act[...],
//     mocap_pos[...], mocap_quat[...] (anything whose role is "input");
//   - what was measured: qpos[...], qvel[...], sensordata[...] (state and derived paths).
// That is what `plumb run --format csv` writes, and what the bridge's flight recorder writes:
// there, the columns `kind` and `event` and the link's own `cmd.*` / `state.*` columns are
// read only when a column map names them; rows of kind "event" are skipped. The flight
// recorder ends every line with a newline, so a last line without one was cut short by a kill
// of the bridge: it is left out (RobotLog::last_line_cut).
// An empty cell means "not sampled in this row": each column keeps its own times.
//
// A column map (TOML) renames a robot's own columns to plumb paths, or drops them:
//
//   [columns]
//   "hip_torque" = "qfrc_applied[hip]"
//   "cmd.tau[0]" = "qfrc_applied[hinge]"
//   "qfrc_applied[0]" = ""          # not used
//
// Example:
//   plumb::RobotLog log = plumb::LoadRobotLog(model, "decay.csv");
//   for (const plumb::LogSignal& s : log.measured) ...
//
// Thread-safety: LoadColumnMap and LoadRobotLog read their files, only read `model` and keep no
// state: they may be called from several threads at once.

#ifndef PLUMB_INCLUDE_PLUMB_ROBOT_LOG_H_
#define PLUMB_INCLUDE_PLUMB_ROBOT_LOG_H_

#include <map>
#include <string>
#include <vector>

#include "plumb/model.h"
#include "plumb/notice.h"
#include "plumb/path.h"

namespace plumb {

// One column of a log: a single element of the model's arrays, sampled at its own times.
struct LogSignal {
  std::string column;         // as the file names it
  Path path;                  // one element (count 1)
  std::vector<double> time;   // s, non-decreasing
  std::vector<double> value;  // in the path's units
};

struct RobotLog {
  std::string source;               // the file
  double start = 0;                 // the first time in the file, s
  double end = 0;                   // the last
  std::vector<LogSignal> inputs;    // applied (role "input")
  std::vector<LogSignal> measured;  // measured (role "state" or "derived")
  bool last_line_cut = false;       // a flight log's last line had no newline: left out
};

// Column name -> plumb path; an empty path drops the column.
struct ColumnMap {
  std::string source;
  std::map<std::string, std::string> columns;
};

// Reads a column map. @throws IoError when unreadable; ValueError naming file:line for
// anything but a [columns] table of strings.
ColumnMap LoadColumnMap(const std::string& path);

// Reads and checks a log against `model`. `timestep` is the simulation's (a log must span at
// least one). @throws IoError when unreadable; ValueError naming the file, row (1 = the
// header) and column for: no header or no time column, a cell that is not a number, NaN or
// infinity, time going backwards, an unknown column (with the nearest paths), a parameter
// column, a path of more than one element, two columns for one path, no measured column, or
// a log shorter than one timestep.
RobotLog LoadRobotLog(const Model& model, const std::string& path, double timestep,
                      const ColumnMap& map = {});

// Every log of `paths` at the model's timestep, with the column map at `column_map` (none when
// empty) applied to each. A log whose last line was cut short says so (last_line_cut), and
// gets a note (NoticeTopic::kLog) in `notices` when given.
// @throws as LoadColumnMap and LoadRobotLog do.
std::vector<RobotLog> LoadRobotLogs(const Model& model, const std::vector<std::string>& paths,
                                    const std::string& column_map, Notices* notices = nullptr);

}  // namespace plumb

#endif  // PLUMB_INCLUDE_PLUMB_ROBOT_LOG_H_
