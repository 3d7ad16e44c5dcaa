// Reports: self-contained pages, written whole or not at all, with the charts and pictures
// the checks call for. (tests/report/browser_check.py opens them in Chromium.)

#include "plumb/report.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <regex>

#include "fixture.h"
#include "plumb/error.h"
#include "plumb/render.h"
#include "sim/log_maker.h"

namespace plumb {
namespace {

int Count(const std::string& text, const std::string& what) {
  int n = 0;
  for (std::size_t at = text.find(what); at != std::string::npos; at = text.find(what, at + 1)) {
    ++n;
  }
  return n;
}

// Nothing in the page may load from elsewhere: no src/href to a URL, no import, no fetch.
void ExpectSelfContained(const std::string& html) {
  EXPECT_EQ(html.find("src=\"http"), std::string::npos);
  EXPECT_EQ(html.find("href=\"http"), std::string::npos);
  EXPECT_EQ(html.find("<link"), std::string::npos);
  EXPECT_NE(html.find("default-src 'none'"), std::string::npos);
  EXPECT_NE(html.find("Chart.js v3.9"), std::string::npos);  // inlined
}

struct PendulumCase {
  Model model = Model::Load(testing::kPendulum);
  VerifyOptions options;
  PendulumCase() { options.sets = {ParseAssignment(model, "qpos[hinge]=0.7")}; }
};

TEST(ReportTest, VerifyReportHasTheChecksChartsAndPictures) {
  PendulumCase c;
  VerifyReport result = Verify(c.model, c.options);
  testing::TempDir dir;
  ReportInfo info{{"plumb", "verify", "models/pendulum.xml"}};
  WriteVerifyReport(dir.File("r.html"), c.model, c.options.sets, result, info);
  std::string html = testing::ReadFile(dir.File("r.html"));
  ExpectSelfContained(html);
  EXPECT_LT(html.size(), 3u << 20);  // a few MB at most
  EXPECT_NE(html.find("plumb verify models/pendulum.xml"), std::string::npos);
  EXPECT_NE(html.find(MujocoVersion()), std::string::npos);
  EXPECT_EQ(Count(html, "<td class=\"status "), static_cast<int>(result.checks.size()));
  // q(t), q̇(t), phase portrait, energy, convergence, period: six charts, each explained
  EXPECT_EQ(Count(html, "class=\"plumb-chart\""), 6);
  EXPECT_EQ(Count(html, "How to read this."), 6);
  EXPECT_NE(html.find("\"log\":true"), std::string::npos);  // the log-log convergence axes
  EXPECT_NE(html.find("exact (elliptic integral)"), std::string::npos);
  if (RendererBuilt() && html.find("No pictures:") == std::string::npos) {
    EXPECT_EQ(Count(html, "src=\"data:image/png;base64,"), 3)
        << "start, end and the animation's first frame";
    EXPECT_NE(html.find("class=\"flipbook\""), std::string::npos);
  }
}

TEST(ReportTest, VerifyKeepsWhatItsChecksMeasured) {
  PendulumCase c;
  VerifyReport result = Verify(c.model, c.options);
  const VerifyFigures& f = result.figures;
  ASSERT_GT(f.t.size(), 100u);
  ASSERT_EQ(f.q.size(), 1u);
  EXPECT_EQ(f.coords[0], "qpos[hinge]");
  EXPECT_DOUBLE_EQ(f.q[0][0], 0.7);
  EXPECT_EQ(f.qdot[0].size(), f.t.size());
  EXPECT_EQ(f.energy.size(), f.t.size());
  // the chapter's numbers are in the curve: q(0.1 s) = 0.65403
  std::size_t at = std::size_t(std::lround(0.1 / 0.002));
  EXPECT_NEAR(f.q[0][at], testing::kChapterQ[0], 5e-6);
  EXPECT_NEAR(f.qdot[0][at], testing::kChapterDq[0], 5e-6);
  ASSERT_GE(f.convergence.levels.size(), 3u);
  EXPECT_NEAR(f.expected_order, 1, 1e-12);  // Euler
  ASSERT_TRUE(f.pendulum.has_value());
  const PendulumFigures& pendulum = *f.pendulum;
  ASSERT_EQ(pendulum.periods.size(), 3u);
  for (const auto& p : pendulum.periods) EXPECT_NEAR(p.period / p.exact, 1, 1e-6);
  EXPECT_EQ(pendulum.exact_curve.size(), 60u);
  EXPECT_GT(pendulum.exact_curve.back().exact, 1.5 * pendulum.small_angle_period);  // 3 rad: much longer
}

TEST(ReportTest, AuditReportHasStepResponsesSettleAndThumbnails) {
  // an arm whose light hand is flagged: the finding names a body, so it gets a thumbnail
  Model model = Model::FromXmlString(R"(
    <mujoco model="arm"><option timestep="0.002"/>
      <worldbody><geom name="floor" type="plane" size="2 2 0.1"/>
        <body name="upper" pos="0 0 1"><joint name="shoulder" axis="0 1 0" damping="0.5"/>
          <geom type="capsule" fromto="0 0 0 0.4 0 0" size="0.04" mass="1"/>
          <body name="hand" pos="0.4 0 0"><joint name="wrist" axis="0 1 0" damping="0.1"/>
            <geom type="sphere" size="0.03" mass="1e-7"/></body></body></worldbody>
      <actuator><position name="servo" joint="shoulder" kp="50" ctrlrange="-1 1" ctrllimited="true"/></actuator>
    </mujoco>)",
                                     "arm.xml");
  AuditOptions options;
  AuditReport result = Audit(model, options);
  ASSERT_FALSE(result.step_responses.empty());
  EXPECT_TRUE(std::isfinite(result.step_responses[0].target));
  ASSERT_EQ(result.settle.size(), 2u);
  EXPECT_GT(result.settle[0].t.size(), 10u);
  bool names_hand = false;
  for (const CheckRow& f : result.findings) {
    names_hand = names_hand || (f.element.name == "hand" && f.status != CheckStatus::kPass);
  }
  ASSERT_TRUE(names_hand) << "the light hand should be flagged";
  testing::TempDir dir;
  WriteAuditReport(dir.File("a.html"), model, {}, result, ReportInfo{});
  std::string html = testing::ReadFile(dir.File("a.html"));
  ExpectSelfContained(html);
  EXPECT_EQ(Count(html, "class=\"plumb-chart\""), 3);  // step responses, energy, speed
  EXPECT_NE(html.find("Layer: inertia"), std::string::npos);
  EXPECT_EQ(result.start, "qpos0");  // the start the audit judged from, in the header
  EXPECT_NE(html.find("<dt>start</dt><dd>qpos0</dd>"), std::string::npos);
  if (RendererBuilt() && html.find("No thumbnails") == std::string::npos) {
    EXPECT_NE(html.find("alt=\"body &#39;hand&#39;"), std::string::npos);
  }
}

TEST(ReportTest, TheAnimationHasTheFramesAskedFor) {
  if (!RendererBuilt()) GTEST_SKIP() << "no renderer in this build";
  PendulumCase c;
  VerifyReport result = Verify(c.model, c.options);
  testing::TempDir dir;
  ReportInfo info;
  info.frames = 4;
  WriteVerifyReport(dir.File("r.html"), c.model, c.options.sets, result, info);
  std::string html = testing::ReadFile(dir.File("r.html"));
  if (html.find("No pictures:") != std::string::npos) GTEST_SKIP() << "no GL context here";
  // the two stills, the flipbook's first frame, and in its list t = 0 and the 4 frames
  EXPECT_EQ(Count(html, "data:image/png;base64,"), 2 + 1 + 1 + 4);
  info.frames = 0;  // the stills only
  WriteVerifyReport(dir.File("s.html"), c.model, c.options.sets, result, info);
  html = testing::ReadFile(dir.File("s.html"));
  EXPECT_EQ(Count(html, "data:image/png;base64,"), 2);
  EXPECT_EQ(html.find("class=\"flipbook\""), std::string::npos);
}

// The pictures a command starts before its check (StartPictures, drawn on their own thread
// while the check runs) are the pictures the report would draw itself: the same PNGs, byte for
// byte, stills and animation; and an audit's thumbnails come from that same renderer.
TEST(ReportTest, PicturesDrawnAheadAreThePicturesDrawnAfter) {
  if (!RendererBuilt()) GTEST_SKIP() << "no renderer in this build";
  PendulumCase c;
  ReportInfo info;
  info.frames = 3;
  info.ahead = StartPictures(c.model, c.options.sets, info);
  VerifyReport result = Verify(c.model, c.options);
  testing::TempDir dir;
  WriteVerifyReport(dir.File("ahead.html"), c.model, c.options.sets, result, info);
  info.ahead = nullptr;
  WriteVerifyReport(dir.File("after.html"), c.model, c.options.sets, result, info);
  auto pngs = [](const std::string& html) {
    std::vector<std::string> out;
    for (std::size_t at = html.find("data:image/png;base64,"); at != std::string::npos;
         at = html.find("data:image/png;base64,", at + 1)) {
      out.push_back(html.substr(at, html.find_first_of("\"&", at) - at));
    }
    return out;
  };
  std::string ahead = testing::ReadFile(dir.File("ahead.html"));
  if (ahead.find("No pictures:") != std::string::npos) GTEST_SKIP() << "no GL context here";
  std::vector<std::string> drawn_ahead = pngs(ahead);
  EXPECT_EQ(drawn_ahead.size(), 2u + 1 + 1 + 3);
  EXPECT_EQ(drawn_ahead, pngs(testing::ReadFile(dir.File("after.html"))));
}

// A log whose replay leaves only its noise (the right model, measured with a noise of 5.5 % of
// each signal's spread) fits at about 94.5 %, which a fixed 95 % threshold marked WARN; judged
// against the noise the log's differences show, it passes. A model with the wrong damping,
// whose error is a slow wave well above the noise, does not.
TEST(ReportTest, PureNoiseResidualsPassTheFitThreshold) {
  testing::TempDir dir;
  testing::LogSpec spec;
  spec.set = {"qpos[hinge]=0.7"};
  spec.until = 3;
  spec.noise = {0.0, 0.0};
  Model model = Model::Load(testing::kPendulum);
  RobotLog clean =
      LoadRobotLog(model, testing::MakeLog(dir.File("clean.csv"), spec), model->opt.timestep);
  ReplayResult exact = Replay(model, clean, {});
  spec.noise.clear();
  for (const SignalFit& f : exact.signals) {
    double spread = 0, mean = 0;
    const std::vector<double>& v = clean.measured[spec.noise.size()].value;
    for (double x : v) mean += x / v.size();
    for (double x : v) spread += (x - mean) * (x - mean) / v.size();
    spec.noise.push_back(0.055 * std::sqrt(spread));
    EXPECT_EQ(FitStatus(f), CheckStatus::kPass) << f.column;  // no error at all
  }
  RobotLog noisy =
      LoadRobotLog(model, testing::MakeLog(dir.File("noisy.csv"), spec), model->opt.timestep);
  ReplayResult r = Replay(model, noisy, {});
  for (const SignalFit& f : r.signals) {
    EXPECT_LT(f.fit, 95) << f.column;  // the old threshold's WARN
    EXPECT_GT(f.fit, 93) << f.column;
    EXPECT_NEAR(f.noise_fit, f.fit, 1.5) << f.column;
    EXPECT_EQ(FitStatus(f), CheckStatus::kPass)
        << f.column << " rms " << f.rms << " noise " << f.noise;
  }
  Model wrong = model.Clone();
  ApplyParameterAssignments(wrong, {"dof_damping[hinge]=0.2"});
  for (const SignalFit& f : Replay(wrong, noisy, {}).signals) {
    EXPECT_NE(FitStatus(f), CheckStatus::kPass) << f.column << " fit " << f.fit;
  }
}

TEST(ReportTest, AnUnwritableReportLeavesNothing) {
  PendulumCase c;
  VerifyReport result;
  result.model = "x";
  testing::TempDir dir;
  ReportInfo info;
  info.pictures = false;
  EXPECT_THROW(WriteVerifyReport(dir.File("missing/r.html"), c.model, {}, result, info), IoError);
  EXPECT_TRUE(std::filesystem::is_empty(dir.path()));
}

TEST(ReportTest, BatchCollectorKeepsAFixedUniformSample) {
  BatchCollector a({"p"}, {"m"}, 100), b({"p"}, {"m"}, 100);
  for (int i = 0; i < 10000; ++i) {
    a.Add({double(i)}, {double(i) * 2}, i % 10 == 0);
    b.Add({double(i)}, {double(i) * 2}, i % 10 == 0);
  }
  EXPECT_EQ(a.total(), 10000);
  EXPECT_EQ(a.diverged(), 1000);
  ASSERT_EQ(a.kept().size(), 100u);
  double mean = 0;
  long late = 0;
  for (std::size_t i = 0; i < a.kept().size(); ++i) {
    EXPECT_EQ(a.kept()[i].parameters, b.kept()[i].parameters);  // the same batch, the same sample
    mean += a.kept()[i].parameters[0] / 100;
    late += a.kept()[i].parameters[0] >= 5000;
  }
  EXPECT_NEAR(mean, 5000, 1000);  // uniform over the batch, not its first 100
  EXPECT_GT(late, 25);
}

TEST(ReportTest, BatchReportMarksDivergedCases) {
  PendulumCase c;
  BatchCollector batch({"dof_damping[hinge]"}, {"qpos[hinge]@2"});
  for (int i = 0; i < 50; ++i) {
    bool diverged = i % 7 == 0;
    batch.Add({0.02 * i}, {diverged ? NAN : 0.5 - 0.01 * i}, diverged);
  }
  testing::TempDir dir;
  ReportInfo info;
  info.pictures = false;
  WriteBatchReport(dir.File("b.html"), "sweep", c.model, c.options.sets, batch, info);
  std::string html = testing::ReadFile(dir.File("b.html"));
  ExpectSelfContained(html);
  EXPECT_NE(html.find("diverged (drawn at the lowest value)"), std::string::npos);
  // a histogram of the metric, the metric against the parameter, outcomes by parameter
  EXPECT_EQ(Count(html, "class=\"plumb-chart\""), 3);
  EXPECT_NE(html.find("<td class=\"FAIL\">8</td>"), std::string::npos);  // 8 of 50 diverged
}

TEST(ReportTest, ConvergeReportShowsTheLadder) {
  PendulumCase c;
  ConvergenceResult r =
      Converge(c.model, c.options.sets, ParseMetric(c.model, "qpos[hinge]@2"), 0.002, 4, 1e-3, 2);
  testing::TempDir dir;
  ReportInfo info;
  info.pictures = false;
  WriteConvergeReport(dir.File("c.html"), c.model, c.options.sets, {r}, mjINT_EULER, info);
  std::string html = testing::ReadFile(dir.File("c.html"));
  ExpectSelfContained(html);
  EXPECT_EQ(Count(html, "class=\"plumb-chart\""), 1);
  EXPECT_NE(html.find("expected slope 1"), std::string::npos);
  EXPECT_EQ(Count(html, "<tr><td>"), static_cast<int>(r.levels.size()));
}

}  // namespace
}  // namespace plumb
