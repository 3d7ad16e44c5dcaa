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

}  // namespace
}  // namespace plumb
