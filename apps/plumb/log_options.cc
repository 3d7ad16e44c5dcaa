// Shared by plumb replay and plumb identify (log_options.h).

#include "log_options.h"

#include "cli_common.h"

namespace plumb::cli {

std::vector<RobotLog> LoadLogs(const Model& model, const std::vector<std::string>& paths,
                               const std::string& column_map) {
  return LoadRobotLogs(model, paths, column_map, &CommandNotices());
}

}  // namespace plumb::cli
