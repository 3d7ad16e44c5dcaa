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
