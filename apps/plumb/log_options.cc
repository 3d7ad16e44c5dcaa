// Shared by plumb replay and plumb identify (log_options.h).

#include "log_options.h"

#include <fmt/format.h>

#include <cmath>
#include <cstdio>

#include "plumb/error.h"

namespace plumb::cli {

std::vector<RobotLog> LoadLogs(const Model& model, const std::vector<std::string>& paths,
                               const std::string& column_map) {
  ColumnMap map;
  if (!column_map.empty()) map = LoadColumnMap(column_map);
  std::vector<RobotLog> logs;
  for (const std::string& path : paths) {
    logs.push_back(LoadRobotLog(model, path, model->opt.timestep, map));
    if (logs.back().last_line_cut) {
      std::fprintf(stderr,
                   "plumb: note: %s: the last line is cut short (the bridge was killed while "
                   "writing it); it is left out\n",
                   path.c_str());
    }
  }
  return logs;
}

void ApplyParameterSets(Model& model, const std::vector<std::string>& sets) {
  std::vector<Assignment> edits;
  for (const std::string& text : sets) {
    Assignment a = ParseAssignment(model, text);
    if (a.path.role != Role::kParameter) {
      throw ValueError(fmt::format(
          "--set '{}': {} is {} {}; here the state and the inputs come from the log, and --set "
          "takes model parameters (dof_damping[...], body_mass[...], opt.timestep, ...)",
          text, a.path.text, a.path.role == Role::kInput ? "an" : "a", RoleName(a.path.role)));
    }
    edits.push_back(std::move(a));
  }
  Data scratch(model);
  if (WriteParameters(model, scratch, edits)) mj_setConst(model.get_mutable(), scratch.get());
}

}  // namespace plumb::cli
