// Shared by plumb replay and plumb identify (log_options.h).

#include "log_options.h"

#include <cstdio>

namespace plumb::cli {

std::vector<RobotLog> LoadLogs(const Model& model, const std::vector<std::string>& paths,
                               const std::string& column_map) {
  std::vector<RobotLog> logs = LoadRobotLogs(model, paths, column_map);
  for (const RobotLog& log : logs) {
    if (!log.last_line_cut) continue;
    std::fprintf(stderr,
                 "plumb: note: %s: the last line is cut short (the bridge was killed while "
                 "writing it); it is left out\n",
                 log.source.c_str());
  }
  return logs;
}

}  // namespace plumb::cli
