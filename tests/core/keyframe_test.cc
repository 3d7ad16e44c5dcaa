#include "plumb/keyframe.h"

#include <gtest/gtest.h>

#include <cmath>

#include "fixture.h"
#include "keyed_model.h"
#include "plumb/error.h"
#include "plumb/run.h"

namespace plumb {
namespace {

using KeyframeTest = testing::MujocoTest;

TEST_F(KeyframeTest, AssignmentsMatchMjResetDataKeyframe) {
  Model model = Model::FromXmlString(testing::kKeyed, "keyed.xml");
  for (const char* name : {"home", "away"}) {
    Data ours(model), mujocos(model);
    ApplyAssignments(model, ours, KeyframeAssignments(model, name));
    mj_resetDataKeyframe(model.get(), mujocos.get(), FindKeyframe(model, name));
    mj_forward(model.get(), mujocos.get());
    EXPECT_EQ(ours->time, mujocos->time) << name;
    EXPECT_EQ(ours->qpos[0], mujocos->qpos[0]) << name;
    EXPECT_EQ(ours->qvel[0], mujocos->qvel[0]) << name;
    EXPECT_EQ(ours->ctrl[0], mujocos->ctrl[0]) << name;
    for (int i = 0; i < 3; ++i) EXPECT_EQ(ours->mocap_pos[i], mujocos->mocap_pos[i]) << name;
    for (int i = 0; i < 4; ++i) EXPECT_EQ(ours->mocap_quat[i], mujocos->mocap_quat[i]) << name;
  }
}

// MuJoCo 4.0's plastic springs: a keyframe's plastic state (a yielded spring's rest offset)
// starts the run as mj_resetDataKeyframe starts it, and a second later the joint is where
// MuJoCo's own run puts it, to the last bit; plastic[] can be set like any other state.
TEST_F(KeyframeTest, APlasticKeyframeStartsWhereMujocosResetDoes) {
#if mjVERSION_HEADER >= 4000000
  Model model = Model::FromXmlString(R"(<mujoco><option gravity="0 0 0"/><worldbody>
      <body pos="0 0 1"><joint name="j" axis="0 1 0" stiffness="10" springyield="1" damping="1"/>
        <geom type="capsule" fromto="0 0 0 0.3 0 0" size="0.03" mass="1"/></body></worldbody>
      <actuator><motor name="m" joint="j" delay="0.01" nsample="5"/></actuator>
      <keyframe><key name="bent" qpos="0" ctrl="0.2" plastic="0.4"/></keyframe></mujoco>)");
  Data ours(model), mujocos(model);
  ApplyAssignments(model, ours, KeyframeAssignments(model, "bent"));
  mj_resetDataKeyframe(model.get(), mujocos.get(), FindKeyframe(model, "bent"));
  mj_forward(model.get(), mujocos.get());
  EXPECT_EQ(ours->plastic[0], 0.4);
  // every part of the state, the delayed motor's history included
  EXPECT_EQ(Snapshot(model, ours, 0).integration, Snapshot(model, mujocos, 0).integration);
  for (int i = 0; i < 500; ++i) {
    mj_step(model.get(), ours.get());
    mj_step(model.get(), mujocos.get());
  }
  EXPECT_EQ(ours->qpos[0], mujocos->qpos[0]);
  EXPECT_GT(std::fabs(ours->qpos[0]), 1e-3);  // the offset rest pulls the joint away from 0
  Data set(model);
  ApplyAssignments(model, set, {ParseAssignment(model, "plastic[0]=0.4")});
  EXPECT_EQ(set->plastic[0], 0.4);
#else
  GTEST_SKIP() << "plastic springs came with MuJoCo 4.0";
#endif
}

// One reference pose for every command: the named keyframe, else "home", else "test", else
// qpos0; and the user's state assignments win over the keyframe's.
TEST_F(KeyframeTest, TheReferencePoseIsNamedThenHomeThenTestThenQpos0) {
  Model keyed = Model::FromXmlString(testing::kKeyed, "keyed.xml");
  ReferencePose home = FindReferencePose(keyed);
  EXPECT_EQ(home.keyframe, FindKeyframe(keyed, "home"));
  EXPECT_EQ(home.description, "keyframe 'home'");
  ReferencePose away = FindReferencePose(keyed, "away");
  EXPECT_EQ(away.keyframe, FindKeyframe(keyed, "away"));
  EXPECT_EQ(away.description, "keyframe 'away' (named by the caller)");
  EXPECT_THROW(FindReferencePose(keyed, "nowhere"), ValueError);
  const char* test_only = R"(<mujoco><worldbody><body><joint name="s" type="slide"/>
      <geom type="box" size="0.1 0.1 0.1"/></body></worldbody>
      <keyframe><key name="other" qpos="2"/><key name="test" qpos="1"/></keyframe></mujoco>)";
  Model test = Model::FromXmlString(test_only, "test.xml");
  EXPECT_EQ(FindReferencePose(test).keyframe, 1);
  Model none = Model::FromXmlString(R"(<mujoco><worldbody><body><joint type="slide"/>
      <geom type="box" size="0.1 0.1 0.1"/></body></worldbody></mujoco>)",
                                    "none.xml");
  EXPECT_EQ(FindReferencePose(none).keyframe, -1);
  EXPECT_EQ(FindReferencePose(none).description, "qpos0");
  // the keyframe first, then the user's state on top; parameters stay applied
  Data data(test);
  StartAtPose(test, data, FindReferencePose(test),
              {ParseAssignment(test, "dof_damping[s]=3"), ParseAssignment(test, "qvel[s]=0.5")});
  EXPECT_EQ(data->qpos[0], 1);
  EXPECT_EQ(data->qvel[0], 0.5);
  EXPECT_EQ(test->dof_damping[0], 3);
}

// Issue 49: a keyframe by its id (Python's keyframe=1, "#1"), named ones too; a keyframe
// named "#0" keeps its name first.
TEST_F(KeyframeTest, AKeyframeByItsId) {
  const char* xml = R"(<mujoco><worldbody><body><joint name="s" type="slide"/>
      <geom type="box" size="0.1 0.1 0.1"/></body></worldbody>
      <keyframe><key name="other" qpos="2"/><key name="#0" qpos="1"/></keyframe></mujoco>)";
  Model model = Model::FromXmlString(xml, "ids.xml");
  EXPECT_EQ(FindKeyframe(model, "#1"), 1);
  EXPECT_EQ(FindKeyframe(model, "#0"), 1);  // the name wins
  EXPECT_EQ(FindKeyframe(model, "other"), 0);
  EXPECT_THROW(FindKeyframe(model, "#2"), ArgumentError);
  EXPECT_THROW(FindKeyframe(model, "#-1"), ArgumentError);
}

TEST_F(KeyframeTest, SetAppliesOnTop) {
  Model model = Model::FromXmlString(testing::kKeyed, "keyed.xml");
  Data data(model);
  std::vector<Assignment> start = KeyframeAssignments(model, "home");
  start.push_back(ParseAssignment(model, "qvel[slider]=0"));
  ApplyAssignments(model, data, start);
  EXPECT_EQ(data->qpos[0], 0.5);
  EXPECT_EQ(data->qvel[0], 0);
}

// A floating base and two hinges: nq = 9.
constexpr const char* kFloating = R"(<mujoco><worldbody><body name="base"><freejoint name="root"/>
    <geom type="box" size="0.1 0.1 0.05"/>
    <body><joint name="hip" axis="0 1 0"/><geom type="capsule" fromto="0 0 0 0 0 -0.2" size="0.02"/>
      <body pos="0 0 -0.2"><joint name="knee" axis="0 1 0"/>
        <geom type="capsule" fromto="0 0 0 0 0 -0.2" size="0.02"/></body></body></body>
  </worldbody></mujoco>)";

// A start value MuJoCo changes (a ctrl outside its ctrlrange, clamped) is a kStart warning on
// the call's channel, naming the assignment as the caller wrote it: Python's argument "set",
// the plumb command's flag "--set" (the prefix "--").
TEST_F(KeyframeTest, AStartValueMujocoChangesIsAStartWarning) {
  Model model = Model::FromXmlString(
      testing::TwoHingeArm(R"(<motor name="m" joint="a" ctrlrange="-1 1" ctrllimited="true"/>)"));
  Notices python;
  std::vector<Assignment> start =
      StartAssignments(model, {"", "", "", {"ctrl[m]=5", "ctrl[m]=0.5"}}, &python);
  ASSERT_EQ(start.size(), 2u);
  std::vector<Notice> said = python.all();
  ASSERT_EQ(said.size(), 1u);
  const Notice& n = said[0];
  EXPECT_EQ(n.level, NoticeLevel::kWarning);
  EXPECT_EQ(n.topic, NoticeTopic::kStart);
  EXPECT_EQ(n.subject, "set 'ctrl[m]=5'");
  ASSERT_EQ(start[0].warnings.size(), 1u);
  EXPECT_EQ(n.text, start[0].warnings[0]);
  EXPECT_NE(n.text.find("ctrlrange"), std::string::npos) << n.text;
  Notices cli;
  StartAssignments(model, {"", "", "1,0", {"ctrl[m]=-3"}}, &cli, "--");
  ASSERT_EQ(cli.all().size(), 1u);
  EXPECT_EQ(cli.all()[0].Line().rfind("warning: --set 'ctrl[m]=-3': ", 0), 0u)
      << cli.all()[0].Line();
  EXPECT_NO_THROW(StartAssignments(model, {"", "", "", {"ctrl[m]=5"}}));  // no channel
}

TEST_F(KeyframeTest, AWholeQposStartsTheRunThere) {
  Model model = Model::FromXmlString(kFloating, "floating.xml");
  Data data(model);
  ApplyAssignments(model, data, {QposAssignment(model, "0 0 0.08, 1 0 0 0  1.2 -2.5")});
  EXPECT_EQ(data->qpos[2], 0.08);
  EXPECT_EQ(data->qpos[7], 1.2);
  EXPECT_EQ(data->qpos[8], -2.5);
}

TEST_F(KeyframeTest, AQposOfTheWrongLengthNamesNqAndItsMakeUp) {
  Model model = Model::FromXmlString(kFloating, "floating.xml");
  try {
    QposAssignment(model, "1.2,-2.5");
    FAIL() << "no error";
  } catch (const ArgumentError& e) {
    EXPECT_EQ(e.argument(), "qpos");
    EXPECT_NE(e.problem().find("2 values, but 'floating.xml' has nq = 9 (a free joint (7: x y z, "
                               "quaternion w x y z), 2 hinges)"),
              std::string::npos)
        << e.what();
  }
  EXPECT_THROW(QposAssignment(model, "0 0 0.08 1 0 0 0 1.2 nan"), ArgumentError);
}

TEST_F(KeyframeTest, APoseFileIsAssignmentsOrAWholeQpos) {
  Model model = Model::FromXmlString(kFloating, "floating.xml");
  testing::TempDir dir;
  testing::WriteFile(dir.File("lines.txt"),
                     "# lying down\nqpos[root][2]=0.08\n\nqpos[hip]=1.2\nqpos[knee]=-2.5\n");
  testing::WriteFile(dir.File("vector.txt"), "0 0 0.08 1 0 0 0\n1.2 -2.5\n");
  for (const char* file : {"lines.txt", "vector.txt"}) {
    Data data(model);
    ApplyAssignments(model, data, PoseFileAssignments(model, dir.File(file)));
    EXPECT_EQ(data->qpos[2], 0.08) << file;
    EXPECT_EQ(data->qpos[7], 1.2) << file;
    EXPECT_EQ(data->qpos[8], -2.5) << file;
  }
  testing::WriteFile(dir.File("bad.txt"), "qpos[hip]=1.2\nqpos[elbow]=1\n");
  try {
    PoseFileAssignments(model, dir.File("bad.txt"));
    FAIL() << "no error";
  } catch (const ArgumentError& e) {
    EXPECT_EQ(e.argument(), "pose");
    EXPECT_NE(e.value().find("bad.txt:2"), std::string::npos) << e.what();
    EXPECT_NE(e.problem().find("elbow"), std::string::npos) << e.what();
  }
  EXPECT_THROW(PoseFileAssignments(model, dir.File("missing.txt")), IoError);
}

TEST_F(KeyframeTest, UnknownNameListsTheKeyframes) {
  Model model = Model::FromXmlString(testing::kKeyed, "keyed.xml");
  try {
    FindKeyframe(model, "hom");
    FAIL();
  } catch (const ValueError& e) {
    EXPECT_NE(std::string(e.what()).find("home, away"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("did you mean: home"), std::string::npos) << e.what();
  }
  EXPECT_TRUE(KeyframeAssignments(model, "").empty());
  EXPECT_THROW(KeyframeAssignments(Model::Load(testing::kPendulum), "home"), ValueError);
}

TEST_F(KeyframeTest, ReferenceStartIsTheKeyframeThenTheSets) {
  Model model = Model::FromXmlString(testing::kKeyed, "keyed.xml");
  ReferencePose home = FindReferencePose(model);
  std::vector<Assignment> sets = {ParseAssignment(model, "qvel[slider]=1")};
  std::vector<Assignment> start = ReferenceStart(model, home, sets);
  ASSERT_GE(start.size(), 2u);
  EXPECT_EQ(start.front().text, "keyframe 'home': time");
  EXPECT_EQ(start.back().text, "qvel[slider]=1");
  EXPECT_EQ(DescribeStart(home, {}), "keyframe 'home'");
  EXPECT_EQ(DescribeStart(home, sets), "keyframe 'home' with qvel[slider]=1");
  std::vector<Assignment> many(4, sets[0]);
  EXPECT_EQ(DescribeStart(home, many), "keyframe 'home' with 4 assignments");
  EXPECT_EQ(ReferenceStart(model, ReferencePose{}, {}).size(), 0u);  // qpos0: nothing to apply
}

// A slide and a ball joint, limited; a box resting on the floor.
constexpr char kLimited[] = R"(
<mujoco>
  <compiler autolimits="true"/>
  <worldbody>
    <geom name="floor" type="plane" size="1 1 0.1"/>
    <body name="cart" pos="0 0 1">
      <joint name="slider" type="slide" axis="1 0 0" range="0.1 0.5"/>
      <geom type="sphere" size="0.05" mass="1" contype="0" conaffinity="0"/>
      <body name="bob" pos="0 0 -0.3">
        <joint name="socket" type="ball" range="0 30"/>
        <geom type="capsule" fromto="0 0 0 0 0 -0.2" size="0.02" mass="0.5"
              contype="0" conaffinity="0"/>
      </body>
    </body>
    <body name="box" pos="0 0 0.09"><freejoint/>
      <geom name="box" type="box" size="0.1 0.1 0.1" mass="1"/></body>
  </worldbody>
</mujoco>)";

TEST_F(KeyframeTest, StartIssuesNamesJointsOutsideTheirRangesAndDeepContacts) {
  Model model = Model::FromXmlString(kLimited, "limited.xml");
  Data data(model);
  data.Forward();  // qpos0: the slider at 0 < 0.1; the box 10 mm into the floor
  std::vector<StartIssue> issues = StartIssues(model, data);
  ASSERT_EQ(issues.size(), 2u) << DescribeStartIssues(issues, 9);
  EXPECT_EQ(issues[0].kind, StartIssue::Kind::kJointOutsideRange);
  EXPECT_EQ(issues[0].element, "joint 'slider' (id 0)");
  EXPECT_EQ(issues[0].unit, "m");
  EXPECT_NEAR(issues[0].lo, 0.1, 1e-12);
  EXPECT_NE(issues[0].text.find("0.1 m below it"), std::string::npos) << issues[0].text;
  EXPECT_EQ(issues[1].kind, StartIssue::Kind::kDeepContact);
  EXPECT_NEAR(issues[1].value, 0.01, 1e-9);  // one issue for the pair (four corners touch)
  EXPECT_NEAR(issues[1].hi, 0.001, 1e-12);   // MuJoCo's default solimp width
  EXPECT_NE(issues[1].element.find("'floor' (id 0) and 'box'"), std::string::npos);
  // inside its range, the ball joint turned 40 degrees (past its 30), the box on the floor
  data->qpos[0] = 0.2;
  data->qpos[1] = std::cos(M_PI / 9);  // quaternion of 40 degrees about x
  data->qpos[2] = std::sin(M_PI / 9);
  data->qpos[7] = 0.1;
  data.Forward();
  issues = StartIssues(model, data);
  ASSERT_EQ(issues.size(), 1u) << DescribeStartIssues(issues, 9);
  EXPECT_EQ(issues[0].element, "joint 'socket' (id 1)");
  EXPECT_NEAR(issues[0].value, 40 * M_PI / 180, 1e-9);
  EXPECT_NEAR(issues[0].hi, 30 * M_PI / 180, 1e-9);
  data->qpos[1] = 1;
  data->qpos[2] = 0;
  data.Forward();
  EXPECT_TRUE(StartIssues(model, data).empty());
}

TEST_F(KeyframeTest, WithoutAKeyframeTheReferencePoseIsWithinTheJointRanges) {
  Model model = Model::FromXmlString(kLimited, "limited.xml");
  ReferencePose pose = FindReferencePose(model);
  EXPECT_EQ(pose.keyframe, -1);
  EXPECT_EQ(pose.description, "qpos0 (1 joint brought into its range)");
  ASSERT_EQ(pose.into_range.size(), 1u);
  ASSERT_EQ(pose.outside.size(), 1u);
  EXPECT_EQ(pose.into_range[0].text, "qpos[slider]=0.104");  // 1% of [0.1, 0.5] inside
  EXPECT_EQ(pose.outside[0].element, "joint 'slider' (id 0)");
  EXPECT_EQ(pose.outside[0].value, 0);
  Data data(model);
  StartAtPose(model, data, pose, {});
  EXPECT_NEAR(data->qpos[0], 0.104, 1e-15);
  // the caller's assignments win
  StartAtPose(model, data, pose, {ParseAssignment(model, "qpos[slider]=0.3")});
  EXPECT_EQ(data->qpos[0], 0.3);
  EXPECT_EQ(ReferenceStart(model, pose, {}).size(), 1u);
  // a keyframe the caller names is taken as it is
  EXPECT_TRUE(FindReferencePose(Model::FromXmlString(testing::kKeyed, "k.xml")).into_range.empty());
}

}  // namespace
}  // namespace plumb
