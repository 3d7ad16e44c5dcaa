// plumb inspect: the chapter's tables for any model, with units.

#include <cstdio>

#include "cli_common.h"
#include "plumb/describe.h"
#include "plumb/json_output.h"
#include "plumb/result_table.h"

namespace plumb::cli {
namespace {

struct InspectOptions {
  std::string model;
  std::vector<std::string> sets;
  std::string format = "table";
};

int RunInspect(const InspectOptions& o) {
  Model model = LoadModel(o.model);
  if (!o.sets.empty()) {
    Data data(model);
    ApplyAssignments(model, data, ParseAssignments(model, o.sets));
  }
  ModelDescription description = Describe(model);
  std::string text = o.format == "json" ? WithNotices(DescriptionToJson(description, MujocoVersion()))
                                        : DescriptionTable(description, MujocoVersion());
  std::fwrite(text.data(), 1, text.size(), stdout);
  return kExitOk;
}

}  // namespace

void SetupInspectCommand(CLI::App& app, Context& ctx) {
  auto o = std::make_shared<InspectOptions>();
  CLI::App* cmd = AddCommand(
      app, "inspect", "Print a model's sizes, options, bodies, joints, actuators and sensors",
      "Examples:\n"
      "  plumb inspect models/pendulum.xml\n"
      "  plumb inspect models/pendulum.xml --format json\n"
      "  plumb inspect models/pendulum.xml --set 'body_mass[link]=2'");
  AddModelOptions(cmd, &o->model, &o->sets, "applied before inspecting");
  AddFormatOption(cmd, &o->format, {"table", "json"});
  cmd->callback([o, &ctx] { ctx.action = [o] { return RunInspect(*o); }; });
}

}  // namespace plumb::cli
