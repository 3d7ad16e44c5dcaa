// plumb audit --report: the findings by layer with thumbnails of the elements they name,
// the step responses and the passive settle.

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <map>

#include "plumb/report.h"
#include "report/page_start.h"

namespace plumb {
namespace {

constexpr std::size_t kMostThumbnails = 40;

bool Drawable(const CheckRow& f) {
  const CheckElement& e = f.element;
  return !e.name.empty() && (e.kind == "body" || e.kind == "geom" || e.kind == "joint");
}

void AddSettle(report::Page* page, const AuditReport& result) {
  if (result.settle.size() < 2 || result.settle[0].t.size() < 2) return;
  const AuditCurve& energy = result.settle[0];
  const AuditCurve& speed = result.settle[1];
  page->Subheading("The passive settle");
  page->BeginGrid();
  report::Chart e("Total energy during the passive settle", {"t (s)"}, {energy.quantity});
  e.series.push_back({"total energy", energy.t, energy.y});
  e.how_to_read =
      "Zero control from the reference pose: the model should fall, bounce a little and "
      "come to rest, so the energy drops and then stays flat. Sick: energy that rises with "
      "no actuator driving (interpenetrating geoms pushing apart, a too-large timestep), or "
      "that keeps oscillating (nothing damps the model: add joint damping or armature).";
  report::Chart s("Fastest joint speed during the passive settle", {"t (s)"},
                  {"max |qvel| (rad/s or m/s)", true});
  s.series.push_back({"max |qvel|", energy.t, speed.y});
  s.how_to_read =
      "On a log axis the largest joint speed should fall by orders of magnitude once the "
      "model has landed: that is coming to rest. Sick: a floor it never drops below (jitter "
      "at contacts: soft contacts or too few solver iterations), or spikes late in the run "
      "(something slips or snaps).";
  page->Add(e);
  page->Add(s);
  page->EndGrid();
}

void AddStepResponses(report::Page* page, const AuditReport& result) {
  if (result.step_responses.empty()) return;
  page->Subheading("Step responses");
  report::Chart chart("Each actuator's response to a step of 10% of its control range",
                      {"t after the step (s)"}, {"share of the step (0 = before, 1 = target)"});
  for (const AuditCurve& c : result.step_responses) {
    if (c.t.size() < 2) continue;
    double goal = std::isfinite(c.target) ? c.target : c.y.back();
    double change = goal - c.start;
    if (!(std::fabs(change) > 1e-12)) continue;
    std::vector<double> t, y;
    for (std::size_t i = 0; i < c.t.size(); ++i) {
      t.push_back(c.t[i] - c.t.front());
      y.push_back((c.y[i] - c.start) / change);
    }
    std::string label = c.label;
    if (label.rfind("step response of ", 0) == 0) label = label.substr(17);
    chart.series.push_back({label + " (" + c.quantity + ")", t, y});
  }
  if (chart.series.empty()) return;
  chart.series.push_back({"target",
                          {0, chart.series.front().x.back()},
                          {1, 1},
                          report::Series::kLine,
                          "#888888",
                          true});
  chart.how_to_read =
      "Gravity and contacts are off, so only the actuator acts. A servo's curve should rise "
      "to 1 (its target) quickly and settle with little overshoot; a motor's force follows "
      "its control at once. Sick: a curve that stays at 0 (no transmission, zero gain), one "
      "that overshoots far past 1 and rings (kp too high for the inertia, too little damping), "
      "or one that settles well short of 1 (a force limit or a spring fighting the servo).";
  page->Add(chart);
}

}  // namespace

void WriteAuditReport(const std::string& path, const Model& model,
                      const std::vector<Assignment>& sets, const AuditReport& result,
                      const ReportInfo& info) {
  report::Page page = report::StartPage("audit", model, info);
  page.Meta("start", result.start);
  // the thumbnails come from the pictures' renderer: a second one cost a Go2 another 0.9 s
  ReportInfo with = info;
  if (with.pictures && !with.ahead) with.ahead = StartPictures(model, sets, info);
  report::AddModelPictures(&page, model, sets, with);

  // one thumbnail per element named by a finding that is not a PASS
  std::vector<std::string> elements;
  for (const CheckRow& f : result.findings) {
    if (f.status == CheckStatus::kPass || !Drawable(f)) continue;
    if (std::find(elements.begin(), elements.end(), f.element.name) == elements.end() &&
        elements.size() < kMostThumbnails) {
      elements.push_back(f.element.name);
    }
  }
  std::string why;
  std::vector<std::string> thumbs = with.ahead
                                        ? report::HighlightThumbnails(*with.ahead, elements, &why)
                                        : std::vector<std::string>{};
  std::map<std::string, std::string> thumb_of;
  for (std::size_t i = 0; i < thumbs.size(); ++i) thumb_of[elements[i]] = thumbs[i];

  page.Heading("Findings");
  // accepted findings (plumb/accept.h) count apart, as in the table
  const std::vector<CheckRow>& findings = result.findings;
  page.StatusSummary(
      CountUnaccepted(findings, CheckStatus::kPass), CountUnaccepted(findings, CheckStatus::kWarn),
      CountUnaccepted(findings, CheckStatus::kFail), CountUnaccepted(findings, CheckStatus::kSkip));
  if (int accepted = CountAccepted(findings); accepted > 0) {
    page.Paragraph(fmt::format("{} accepted finding{} (an accept list): each shows its status and "
                               "the reason it was accepted.",
                               accepted, accepted == 1 ? "" : "s"),
                   "note");
  }
  if (!why.empty()) page.Paragraph("No thumbnails: " + why, "note");
  std::string layer;
  std::string rows;
  auto flush = [&] {
    if (rows.empty()) return;
    page.Subheading("Layer: " + layer);
    page.Html(
        "<table><tr><th>status</th><th>check</th><th>element</th><th>measured</th>"
        "<th>threshold</th><th>what to do</th><th></th></tr>\n" +
        rows + "</table>\n");
    rows.clear();
  };
  for (const CheckRow& f : result.findings) {
    if (f.section != layer) {
      flush();
      layer = f.section;
    }
    auto thumb = thumb_of.find(f.element.name);
    std::string picture =
        Drawable(f) && thumb != thumb_of.end() && f.status != CheckStatus::kPass
            ? fmt::format(
                  "<img class=\"thumb\" alt=\"{0} highlighted\" title=\"{0} highlighted\" "
                  "src=\"{1}\">",
                  report::Escape(f.About()), report::PngDataUri(thumb->second))
            : "";
    // an accepted finding is not highlighted, and says why it was accepted
    std::string what_to_do = !f.accepted.empty() ? "accepted: " + f.accepted
                             : f.fix.empty()     ? f.explanation
                                                 : f.fix;
    rows += fmt::format(
        "<tr class=\"row-{}\">{}<td><code>{}</code></td><td>{}</td><td>{}</td><td>{}</td>"
        "<td class=\"detail\">{}</td><td>{}</td></tr>\n",
        f.accepted.empty() ? CheckStatusName(f.status) : "accepted", report::StatusCell(f.status),
        report::Escape(f.id), report::Escape(f.About()), report::Escape(f.measured_text),
        report::Escape(f.reference_text), report::Escape(what_to_do), picture);
  }
  flush();

  page.Heading("Audit runs");
  AddStepResponses(&page, result);
  AddSettle(&page, result);
  report::WritePage(page, path);
}

}  // namespace plumb
