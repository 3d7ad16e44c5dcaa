// plumb diff --report: a model against its snapshot, change by change.

#include <fmt/format.h>

#include "plumb/report.h"
#include "report/page_start.h"

namespace plumb {
namespace {

// A table of changes: kind, path, old, new, the step where a trajectory departs, in words.
std::string ChangesTable(const std::vector<SnapshotChange>& changes) {
  std::string rows;
  for (const SnapshotChange& c : changes) {
    rows += fmt::format(
        "<tr><td>{}</td><td><code>{}</code></td><td><code>{}</code></td><td><code>{}</code></td>"
        "<td>{}</td><td>{}</td></tr>\n",
        report::Escape(c.kind), report::Escape(c.path), report::Escape(c.old_value),
        report::Escape(c.new_value), c.step > 0 ? std::to_string(c.step) : "",
        report::Escape(c.what));
  }
  return "<table><tr><th>kind</th><th>path</th><th>snapshot</th><th>now</th><th>step</th>"
         "<th>what</th></tr>\n" +
         rows + "</table>\n";
}

}  // namespace

void WriteDiffReport(const std::string& path, const Model& model, const SnapshotDiff& diff,
                     const std::string& snapshot, const ReportInfo& info) {
  report::Page page = report::StartPage("diff", model, info);
  page.Meta("snapshot", snapshot);
  page.Meta("snapshot written by",
            "plumb " + diff.snapshot_plumb_version + ", MuJoCo " + diff.snapshot_mujoco_version);
  std::string sets;
  for (const std::string& s : diff.sets) sets += (sets.empty() ? "" : ", ") + s;
  for (const std::string& s : diff.model_sets) sets += (sets.empty() ? "" : ", ") + s;
  if (!sets.empty()) page.Meta("assignments", sets);
  page.Heading("Verdict");
  CheckStatus status = diff.diverged    ? CheckStatus::kFail
                       : diff.changed() ? CheckStatus::kWarn
                                        : CheckStatus::kPass;
  page.Html(fmt::format(
      "<table><tr>{}<td>{}</td></tr></table>\n", report::StatusCell(status),
      report::Escape(diff.diverged    ? "the golden trajectory diverges now"
                     : diff.changed() ? fmt::format("{} change(s) beyond tol {:g}",
                                                    diff.changes.size(), diff.tol)
                                      : fmt::format("identical within tol {:g}", diff.tol))));
  for (const std::string& note : diff.notes) page.Paragraph(note);
  if (!diff.changes.empty()) {
    page.Heading("Changes");
    page.Html(ChangesTable(diff.changes));
  }
  if (!diff.compiler.empty()) {
    page.Heading("What this MuJoCo's compiler derived differently");
    page.Paragraph(
        "Values the compiler derives from meshes and body sizes: they say the "
        "release changed, not the model.");
    page.Html(ChangesTable(diff.compiler));
  }
  report::WritePage(page, path);
}

}  // namespace plumb
