// plumb diff: a model against its regression snapshot (plumb snapshot writes one), in words.

#include <fmt/format.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "cli_common.h"
#include "core/file_kind.h"
#include "core/input_file.h"
#include "io/atomic_file.h"
#include "plumb/error.h"
#include "plumb/regression.h"
#include "plumb/report.h"
#include "plumb/result_json.h"
#include "plumb/result_table.h"

namespace plumb::cli {
namespace {

struct DiffOptions {
  std::string snapshot;
  std::string model;
  std::vector<std::string> sets;
  double tol = kDiffTolerance;
  std::string format = "table";
  std::string report;  // --report FILE.html
};

// The text of `path` as a snapshot is read (ReadInputFile: a FIFO or a device is refused, not
// waited on), or "" and `readable` false when it cannot be.
std::string ReadWhole(const std::string& path, bool* readable) {
  try {
    std::string text = internal::ReadInputFile(path, internal::InputKind::kSnapshot);
    *readable = true;
    return text;
  } catch (const IoError&) {
    *readable = false;
    return "";
  }
}

// Refuses a snapshot argument that is no snapshot (a model, swapped arguments, an empty
// or binary file), saying what it is and what to run instead. @throws ValueError.
void CheckSnapshotArgument(const DiffOptions& o, const std::string& text) {
  internal::FileKind kind = internal::SniffFileKind(text);
  if (kind == internal::FileKind::kSnapshot || kind == internal::FileKind::kJson ||
      kind == internal::FileKind::kText)
    return;
  std::string what =
      "'" + o.snapshot + "' is " + internal::FileKindName(kind) + ", not a plumb snapshot";
  if (kind == internal::FileKind::kMjcf || kind == internal::FileKind::kXml) {
    bool readable = false;
    std::string second = ReadWhole(o.model, &readable);
    if (readable && internal::SniffFileKind(second) == internal::FileKind::kSnapshot) {
      throw ValueError("the arguments are swapped: " + what + ", and '" + o.model +
                       "' is the snapshot. plumb diff takes the snapshot first: plumb diff " +
                       o.model + " " + o.snapshot);
    }
    throw ValueError(
        what + ". plumb diff compares a model with a snapshot taken earlier: " + "plumb snapshot " +
        o.snapshot + " -o before.snap.json, then plumb diff " + "before.snap.json " + o.model);
  }
  throw ValueError(what + " (JSON written by plumb snapshot MODEL -o FILE). Write a fresh one " +
                   "with plumb snapshot, or restore it from version control.");
}

int RunDiff(const DiffOptions& o, const Context& ctx) {
  internal::RefuseOutputsOntoInputs({{"--report", o.report}},
                                    ModelInputs(o.model, {}, {{"the snapshot", o.snapshot}}));
  std::string text = internal::ReadInputFile(o.snapshot, internal::InputKind::kSnapshot);
  CheckSnapshotArgument(o, text);
  Model model = LoadModel(o.model);
  std::vector<Assignment> sets = ParseAssignments(model, o.sets);
  SnapshotDiff diff;
  try {
    diff = DiffSnapshot(text, model, sets, o.tol);
  } catch (const ArgumentError&) {
    throw;  // a bad --tol, not a damaged snapshot
  } catch (const ValueError& e) {
    throw ValueError(o.snapshot + ": " + e.what() +
                     ". The file is not a snapshot or was damaged: write a fresh one with "
                     "plumb snapshot MODEL -o FILE (or restore it from version control).");
  }
  if (!o.report.empty()) {
    WriteDiffReport(o.report, model, diff, o.snapshot, ReportInfo{ctx.argv});
    std::fprintf(stderr, "plumb: wrote the report %s\n", o.report.c_str());
  }
  std::string out =
      o.format == "json" ? WithNotices(DiffToJson(diff, o.snapshot)) : DiffTable(diff, o.snapshot, "--set ");
  std::fwrite(out.data(), 1, out.size(), stdout);
  if (diff.diverged) return kExitDiverged;
  return diff.changed() ? kExitCheckFailed : kExitOk;
}

}  // namespace

void SetupDiffCommand(CLI::App& app, Context& ctx) {
  auto d = std::make_shared<DiffOptions>();
  CLI::App* diff =
      AddCommand(app, "diff", "Compare a model with its snapshot, in words",
                 "Example:\n  plumb diff robot.snap.json robot.xml --tol 1e-6\n"
                 "Prints each change (dof_damping[hinge]: 0.05 → 0.1, body added: gripper,\n"
                 "trajectory departs at step 37: ...). Exit codes: 0 identical within --tol,\n"
                 "1 changed, 2 bad input, 3 the golden trajectory diverges.\n"
                 "The model is simulated with the snapshot's own --set values, then diff's --set.");
  diff->add_option("snapshot", d->snapshot, "a file written by plumb snapshot")->required();
  AddModelOptions(diff, &d->model, &d->sets, "before comparing");
  diff->add_option("--tol", d->tol, "relative tolerance for numbers")->capture_default_str();
  AddFormatOption(diff, &d->format, {"table", "json"},
                  "table (in words) or json (header, then changes as {path, old, new, kind})");
  AddReportOption(diff, &d->report);
  diff->callback([d, &ctx] { ctx.action = [d, &ctx] { return RunDiff(*d, ctx); }; });
}

}  // namespace plumb::cli
