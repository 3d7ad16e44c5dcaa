// The charts of a report show all their data and fit the model: a long line is drawn from
// its extremes (no peak lost, no axis cut short), and a verify report shows every joint of
// a multi-joint robot with notes for what it is, not for a pendulum.
// (tests/report/browser_check.py checks the same on the live page in Chromium.)

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <nlohmann/json.hpp>

#include "fixture.h"
#include "report/html.h"

namespace plumb {
namespace {

// The chart data a page carries (the JSON Chart.js draws from).
nlohmann::json ChartData(const std::string& html) {
  const std::string open = "<script id=\"plumb-charts\" type=\"application/json\">";
  std::size_t at = html.find(open);
  EXPECT_NE(at, std::string::npos);
  at += open.size();
  return nlohmann::json::parse(html.substr(at, html.find("</script>", at) - at));
}

// A noisy swing of 100,000 samples with one spike the eye must not miss.
struct LongCurve {
  std::vector<double> t, y;
  static constexpr std::size_t kSpike = 31337;
  LongCurve() {
    for (std::size_t i = 0; i < 100000; ++i) {
      t.push_back(i * 1e-4);
      y.push_back(std::sin(i * 1e-3) + 1e-3 * std::sin(i * 1.7));
    }
    y[kSpike] = 5;
  }
};

TEST(HtmlTest, KeepExtremesKeepsEveryPeakAndTheRange) {
  LongCurve c;
  std::vector<std::size_t> kept = report::KeepExtremes(c.t, c.y, 500);
  EXPECT_LE(kept.size(), 6u * 500);
  EXPECT_TRUE(std::is_sorted(kept.begin(), kept.end()));
  EXPECT_EQ(std::adjacent_find(kept.begin(), kept.end()), kept.end()) << "no index twice";
  EXPECT_EQ(kept.front(), 0u);
  EXPECT_EQ(kept.back(), c.t.size() - 1);
  EXPECT_TRUE(std::binary_search(kept.begin(), kept.end(), LongCurve::kSpike));
  double lo = INFINITY;
  for (std::size_t i : kept) lo = std::min(lo, c.y[i]);
  EXPECT_EQ(lo, *std::min_element(c.y.begin(), c.y.end()));
  // a curve a chart can show whole is kept whole
  std::vector<double> x = {3, 1, 2}, y = {0, 5, -1};
  EXPECT_EQ(report::KeepExtremes(x, y, 500), (std::vector<std::size_t>{0, 1, 2}));
}

TEST(HtmlTest, APhasePortraitKeepsItsWholeRange) {
  // x and y both swing: the range of each survives (the pendulum's clipped -0.649)
  std::vector<double> q, v;
  for (int i = 0; i < 50000; ++i) {
    q.push_back(0.7 * std::cos(i * 7e-4) * std::exp(-i * 2e-5));
    v.push_back(-0.7 * std::sin(i * 7e-4) * std::exp(-i * 2e-5));
  }
  std::vector<std::size_t> kept = report::KeepExtremes(q, v, 500);
  double qlo = INFINITY, vlo = INFINITY, vhi = -INFINITY;
  for (std::size_t i : kept) {
    qlo = std::min(qlo, q[i]);
    vlo = std::min(vlo, v[i]);
    vhi = std::max(vhi, v[i]);
  }
  EXPECT_EQ(qlo, *std::min_element(q.begin(), q.end()));
  EXPECT_EQ(vlo, *std::min_element(v.begin(), v.end()));
  EXPECT_EQ(vhi, *std::max_element(v.begin(), v.end()));
}

TEST(HtmlTest, PageDrawsALongLineWithItsSpikeAndEveryScatterPoint) {
  LongCurve c;
  report::Page page("test");
  report::Chart line("a long line", {"t (s)"}, {"y"});
  line.series.push_back({"y", c.t, c.y});
  page.Add(line);
  report::Chart scatter("many points", {"x"}, {"y"});
  std::vector<double> x(5000), y(5000);
  for (std::size_t i = 0; i < x.size(); ++i) x[i] = y[i] = double((i * 7919) % 5000);
  scatter.series.push_back({"cases", x, y, report::Series::kPoints});
  page.Add(scatter);
  nlohmann::json charts = ChartData(page.Render());
  ASSERT_EQ(charts.size(), 2u);
  const nlohmann::json& points = charts[0]["series"][0]["points"];
  EXPECT_LE(points.size(), 3000u);
  double top = -INFINITY;
  for (const auto& p : points) top = std::max(top, p["y"].get<double>());
  EXPECT_EQ(top, 5);
  EXPECT_EQ(charts[1]["series"][0]["points"].size(), 5000u) << "points are all drawn";
}

}  // namespace
}  // namespace plumb
