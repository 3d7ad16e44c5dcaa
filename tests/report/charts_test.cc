// The charts of a report show all their data and fit the model: a long line is drawn from
// its extremes (no peak lost, no axis cut short), and a verify report shows every joint of
// a multi-joint robot with notes for what it is, not for a pendulum.
// (tests/report/browser_check.py checks the same on the live page in Chromium.)

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <nlohmann/json.hpp>

#include "fixture.h"
#include "plumb/report.h"
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

TEST(HtmlTest, PageDrawsLongSignalsWithTheirSpikeAndEveryScatterPoint) {
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
  report::Chart logged("a logged signal", {"t (s)"}, {"y"});
  logged.series.push_back({"logged", c.t, c.y, report::Series::kPoints});
  page.Add(logged);
  nlohmann::json charts = ChartData(page.Render());
  ASSERT_EQ(charts.size(), 3u);
  for (int k : {0, 2}) {  // the line and the points in time order: drawn from their extremes
    const nlohmann::json& points = charts[k]["series"][0]["points"];
    EXPECT_LE(points.size(), 3000u);
    double top = -INFINITY;
    for (const auto& p : points) top = std::max(top, p["y"].get<double>());
    EXPECT_EQ(top, 5) << "the spike of chart " << k;
  }
  EXPECT_EQ(charts[1]["series"][0]["points"].size(), 5000u) << "a scatter is drawn whole";
}

// A small floating robot: a trunk on a free joint and four two-joint legs on a floor.
Model FloatingRobot() {
  std::string legs;
  const char* names[] = {"FL", "FR", "RL", "RR"};
  const double at[4][2] = {{0.2, 0.1}, {0.2, -0.1}, {-0.2, 0.1}, {-0.2, -0.1}};
  for (int k = 0; k < 4; ++k) {
    legs += "<body name=\"" + std::string(names[k]) + "_thigh\" pos=\"" +
            std::to_string(at[k][0]) + " " + std::to_string(at[k][1]) +
            " 0\"><joint name=\"" + names[k] +
            "_hip\" axis=\"0 1 0\" damping=\"0.5\" range=\"-1 1\"/>"
            "<geom type=\"capsule\" fromto=\"0 0 0 0 0 -0.15\" size=\"0.02\" mass=\"0.3\"/>"
            "<body pos=\"0 0 -0.15\"><joint name=\"" +
            names[k] +
            "_knee\" axis=\"0 1 0\" damping=\"0.5\" range=\"-2 0\"/>"
            "<geom type=\"capsule\" fromto=\"0 0 0 0 0 -0.15\" size=\"0.02\" mass=\"0.2\"/>"
            "</body></body>";
  }
  return Model::FromXmlString(
      "<mujoco model=\"dog\"><compiler autolimits=\"true\"/><option timestep=\"0.002\"/><worldbody>"
      "<geom name=\"floor\" type=\"plane\" size=\"2 2 0.1\"/>"
      "<body name=\"trunk\" pos=\"0 0 0.35\"><freejoint/>"
      "<geom type=\"box\" size=\"0.25 0.1 0.05\" mass=\"5\"/>" +
          legs + "</body></worldbody></mujoco>",
      "dog.xml");
}

TEST(ChartsTest, AVerifyReportOfARobotShowsEveryJointWithNotesForARobot) {
  Model model = FloatingRobot();
  VerifyReport result = Verify(model, VerifyOptions{});
  ASSERT_EQ(result.figures.coords.size(), 8u);
  testing::TempDir dir;
  ReportInfo info;
  info.pictures = false;
  WriteVerifyReport(dir.File("r.html"), model, {}, result, info);
  std::string html = testing::ReadFile(dir.File("r.html"));
  // q(t) and q̇(t) in two groups of at most six joints each, all eight joints in each pair
  nlohmann::json charts = ChartData(html);
  int q_lines = 0, qdot_lines = 0, phase = 0;
  for (const auto& c : charts) {
    std::string y = c["y"]["label"];
    if (y == "q (rad or m)") q_lines += int(c["series"].size());
    if (y == "q\u0307 (rad/s or m/s)") qdot_lines += int(c["series"].size());
    if (y == "velocity (rad/s or m/s)") ++phase;
  }
  EXPECT_EQ(q_lines, 8);
  EXPECT_EQ(qdot_lines, 8);
  EXPECT_EQ(phase, 8) << "a phase portrait per joint";
  for (const std::string& coord : result.figures.coords) {
    EXPECT_NE(html.find("Phase portrait of " + coord), std::string::npos) << coord;
  }
  // notes for a floating robot, none for a pendulum
  EXPECT_NE(html.find("a floating robot with no controller"), std::string::npos);
  EXPECT_EQ(html.find("damped pendulum"), std::string::npos);
  EXPECT_EQ(html.find("Angle against velocity"), std::string::npos);
}

TEST(ChartsTest, APendulumKeepsItsPendulumNotes) {
  Model model = Model::Load(testing::kPendulum);
  VerifyOptions options;
  options.sets = {ParseAssignment(model, "qpos[hinge]=0.7")};
  VerifyReport result = Verify(model, options);
  testing::TempDir dir;
  ReportInfo info;
  info.pictures = false;
  WriteVerifyReport(dir.File("r.html"), model, options.sets, result, info);
  std::string html = testing::ReadFile(dir.File("r.html"));
  EXPECT_NE(html.find("A damped pendulum swings"), std::string::npos);
  EXPECT_EQ(html.find("floating robot"), std::string::npos);
  std::size_t first = html.find("Phase portrait of");
  ASSERT_NE(first, std::string::npos);
  EXPECT_EQ(html.find("Phase portrait of", first + 1), std::string::npos) << "one joint, one";
}

}  // namespace
}  // namespace plumb
