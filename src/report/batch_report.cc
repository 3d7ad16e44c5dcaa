// plumb sweep --report and plumb rollout --report: each metric against each varied
// parameter with diverged cases marked, and histograms of the outcomes.

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "plumb/report.h"
#include "report/page_start.h"

namespace plumb {
namespace {

constexpr int kBins = 20;
constexpr const char* kDivergedColour = "#cf222e";

// Bins of [lo, hi] (a unit-wide one around a constant).
std::vector<double> Edges(double lo, double hi) {
  if (!(hi > lo)) {
    lo -= 0.5;
    hi += 0.5;
  }
  std::vector<double> edges;
  for (int i = 0; i <= kBins; ++i) edges.push_back(lo + (hi - lo) * i / kBins);
  return edges;
}

int BinOf(const std::vector<double>& edges, double v) {
  double lo = edges.front(), hi = edges.back();
  int b = static_cast<int>(std::floor((v - lo) / (hi - lo) * kBins));
  return std::clamp(b, 0, kBins - 1);
}

std::pair<double, double> Range(const std::vector<BatchCollector::Case>& cases, bool metric,
                                std::size_t k) {
  double lo = INFINITY, hi = -INFINITY;
  for (const auto& c : cases) {
    double v = metric ? c.metrics[k] : c.parameters[k];
    if (!std::isfinite(v)) continue;
    lo = std::min(lo, v);
    hi = std::max(hi, v);
  }
  return {lo, hi};
}

void MetricAgainstParameters(report::Page* page, const BatchCollector& b, std::size_t m) {
  const std::string& metric = b.metrics()[m];
  auto [lo, hi] = Range(b.kept(), true, m);
  double floor = std::isfinite(lo) ? lo : 0;
  for (std::size_t p = 0; p < b.parameters().size(); ++p) {
    report::Series ok{"finished", {}, {}, report::Series::kPoints};
    report::Series bad{"diverged (drawn at the lowest value)",
                       {},
                       {},
                       report::Series::kPoints,
                       kDivergedColour,
                       false,
                       "crossRot"};
    report::Series unmeasured{"not measured", {},    {},        report::Series::kPoints,
                              "#888888",      false, "triangle"};
    for (const auto& c : b.kept()) {
      double x = c.parameters[p], y = c.metrics[m];
      if (c.diverged) {
        bad.x.push_back(x);
        bad.y.push_back(std::isfinite(y) ? y : floor);
      } else if (std::isfinite(y)) {
        ok.x.push_back(x);
        ok.y.push_back(y);
      } else {
        unmeasured.x.push_back(x);
        unmeasured.y.push_back(floor);
      }
    }
    report::Chart chart(metric + " against " + b.parameters()[p], {b.parameters()[p]}, {metric});
    chart.series.push_back(ok);
    if (!bad.x.empty()) chart.series.push_back(bad);
    if (!unmeasured.x.empty()) chart.series.push_back(unmeasured);
    chart.how_to_read =
        "Each point is one case. Healthy: the metric changes smoothly with the parameter, the "
        "way the physics says it should (the same force moves a heavier body less, more damping "
        "settles it sooner), and the spread at one parameter value is what the other parameters explain. "
        "Sick: red crosses (diverged runs) clustered at one end of a range, which marks the "
        "edge of where the model is stable, or a sudden jump in the metric, which usually "
        "means a contact or limit switching on.";
    page->Add(chart);
  }
}

report::Histogram MetricHistogram(const BatchCollector& b, std::size_t m) {
  auto [lo, hi] = Range(b.kept(), true, m);
  report::Histogram h("Histogram of " + b.metrics()[m], b.metrics()[m]);
  if (!std::isfinite(lo)) return h;
  h.edges = Edges(lo, hi);
  std::vector<long> counts(kBins, 0);
  for (const auto& c : b.kept()) {
    if (!c.diverged && std::isfinite(c.metrics[m])) ++counts[BinOf(h.edges, c.metrics[m])];
  }
  h.groups.push_back({"finished cases", counts});
  h.how_to_read =
      "How the outcome is spread over the cases. Healthy: one hump whose width matches the "
      "randomisation you asked for. Sick: two humps (the model behaves in two different ways: "
      "a foot that sometimes slips, a grasp that sometimes fails), or a long tail of extreme "
      "values (near-divergence). Diverged cases have no value and are counted in the table.";
  return h;
}

report::Histogram ParameterHistogram(const BatchCollector& b, std::size_t p) {
  auto [lo, hi] = Range(b.kept(), false, p);
  report::Histogram h("Outcomes across " + b.parameters()[p], b.parameters()[p]);
  if (!std::isfinite(lo)) return h;
  h.edges = Edges(lo, hi);
  std::vector<long> ok(kBins, 0), bad(kBins, 0);
  for (const auto& c : b.kept()) {
    if (!std::isfinite(c.parameters[p])) continue;
    ++(c.diverged ? bad : ok)[BinOf(h.edges, c.parameters[p])];
  }
  h.groups.push_back({"finished", ok});
  h.groups.push_back({"diverged", bad});
  h.how_to_read =
      "Cases by the value of this parameter, finished and diverged stacked. Healthy: no "
      "diverged cases at all. Sick: diverged cases piling up in some bins: the model is "
      "unstable there (for a mass: too light against its neighbours; for a timestep: too "
      "large; for friction or damping: at zero).";
  return h;
}

}  // namespace

BatchCollector::BatchCollector(std::vector<std::string> parameters,
                               std::vector<std::string> metrics, std::size_t most)
    : parameters_(std::move(parameters)), metrics_(std::move(metrics)), most_(most) {}

void BatchCollector::Add(const std::vector<double>& parameters, const std::vector<double>& metrics,
                         bool diverged) {
  ++total_;
  if (diverged) ++diverged_;
  Case c{parameters, metrics, diverged};
  c.parameters.resize(parameters_.size(), NAN);
  c.metrics.resize(metrics_.size(), NAN);
  if (kept_.size() < most_) {
    kept_.push_back(std::move(c));
    return;
  }
  // reservoir sampling (algorithm R) with a fixed-seed xorshift: every case is kept with
  // the same probability most / total
  random_ ^= random_ << 13;
  random_ ^= random_ >> 7;
  random_ ^= random_ << 17;
  std::uint64_t slot = random_ % std::uint64_t(total_);
  if (slot < most_) kept_[slot] = std::move(c);
}

void WriteBatchReport(const std::string& path, const std::string& kind, const Model& model,
                      const std::vector<Assignment>& sets, const BatchCollector& b,
                      const ReportInfo& info) {
  report::Page page = report::StartPage(kind, model, info);
  report::AddModelPictures(&page, model, sets, info);
  page.Heading("Cases");
  long finished = b.total() - b.diverged();
  page.Html(fmt::format(
      "<table><tr><th>cases</th><th>finished</th><th>diverged</th><th>in the charts</th></tr>"
      "<tr><td>{}</td><td class=\"PASS\">{}</td><td class=\"{}\">{}</td><td>{}{}</td></tr>"
      "</table>\n",
      b.total(), finished, b.diverged() > 0 ? "FAIL" : "PASS", b.diverged(), b.kept().size(),
      std::size_t(b.total()) > b.kept().size() ? " (a uniform sample)" : " (all)"));
  std::string names;
  for (const std::string& p : b.parameters()) names += "<code>" + report::Escape(p) + "</code> ";
  if (!names.empty()) page.Html("<p>Varied: " + names + "</p>\n");
  if (b.kept().empty()) {
    page.Paragraph("No case finished before the run stopped: nothing to chart.", "note");
    report::WritePage(page, path);
    return;
  }
  for (std::size_t m = 0; m < b.metrics().size(); ++m) {
    page.Heading("Metric " + b.metrics()[m]);
    report::Histogram h = MetricHistogram(b, m);
    if (!h.edges.empty()) page.Add(h);
    MetricAgainstParameters(&page, b, m);
  }
  if (!b.parameters().empty()) page.Heading("Where runs diverged");
  for (std::size_t p = 0; p < b.parameters().size(); ++p) {
    report::Histogram h = ParameterHistogram(b, p);
    if (!h.edges.empty()) page.Add(h);
  }
  report::WritePage(page, path);
}

}  // namespace plumb
