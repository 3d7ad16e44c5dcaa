// What plumb replay and plumb identify share: logs with an optional column map, saying on
// stderr which were cut short.

#ifndef PLUMB_APPS_PLUMB_LOG_OPTIONS_H_
#define PLUMB_APPS_PLUMB_LOG_OPTIONS_H_

#include <string>
#include <vector>

#include "plumb/model.h"
#include "plumb/replay.h"
#include "plumb/robot_log.h"

namespace plumb::cli {

// Reads every log against `model` (the column map, when given, applies to each).
std::vector<RobotLog> LoadLogs(const Model& model, const std::vector<std::string>& paths,
                               const std::string& column_map);

}  // namespace plumb::cli

#endif  // PLUMB_APPS_PLUMB_LOG_OPTIONS_H_
