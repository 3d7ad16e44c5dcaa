#include "plumb/keyframe.h"

#include <gtest/gtest.h>

#include "fixture.h"
#include "keyed_model.h"
#include "plumb/error.h"

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
