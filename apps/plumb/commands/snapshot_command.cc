// plumb snapshot: a model's regression snapshot for CI (plumb diff compares one).

#include <fmt/format.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "cli_common.h"
#include "core/file_kind.h"
#include "io/atomic_file.h"
#include "plumb/error.h"
#include "plumb/regression.h"
#include "plumb/result_json.h"
#include "plumb/result_table.h"

namespace plumb::cli {
using internal::AtomicFile;
using internal::RefuseOutputsOntoInputs;

namespace {

struct SnapshotOptions {
  std::string model;
  std::vector<std::string> sets;
  std::string output;
};

int RunSnapshot(const SnapshotOptions& o) {
  RefuseOutputsOntoInputs({{"-o", o.output}}, ModelInputs(o.model));
  Model model = LoadModel(o.model);
  std::vector<Assignment> sets = ParseAssignments(model, o.sets);
  std::string divergence;
  std::string text = MakeSnapshot(model, sets, &divergence);
  if (!divergence.empty()) {
    // a golden trajectory that diverges is no reference: nothing is written
    std::fprintf(stderr,
                 "plumb: no snapshot written: the golden trajectory of %s diverges: %s\n"
                 "Fix the model first (plumb audit %s shows where), e.g. a smaller timestep "
                 "or more damping.\n",
                 o.model.c_str(), divergence.c_str(), o.model.c_str());
    return kExitDiverged;
  }
  AtomicFile file(o.output);
  std::fwrite(text.data(), 1, text.size(), file.stream());
  file.Commit();
  std::fprintf(stderr, "plumb: wrote the snapshot of %s to %s\n", o.model.c_str(),
               o.output == "-" ? "standard output" : o.output.c_str());
  return kExitOk;
}

// Reads a whole file, or "" with `*readable` false.
}  // namespace

void SetupSnapshotCommand(CLI::App& app, Context& ctx) {
  auto s = std::make_shared<SnapshotOptions>();
  CLI::App* snapshot = AddCommand(
      app, "snapshot", "Record a model's structure, inertia, actuators and a golden trajectory",
      "Example:\n  plumb snapshot robot.xml -o robot.snap.json    # commit it with the model\n"
      "The --set values are recorded in the snapshot; plumb diff applies them again.\n"
      "Exit codes: 0 written, 2 bad input, 3 the golden trajectory diverges (nothing is\n"
      "written on 2 or 3).");
  AddModelOptions(snapshot, &s->model, &s->sets, "before snapshotting");
  snapshot->add_option("-o,--output", s->output, "the snapshot file (JSON; '-' for stdout)")
      ->required();
  snapshot->callback([s, &ctx] { ctx.action = [s] { return RunSnapshot(*s); }; });
}

}  // namespace plumb::cli
