// Saving fitted values through mjSpec: every supported field comes back from the saved MJCF.

#include "plumb/model_edit.h"

#include <gtest/gtest.h>

#include <filesystem>

#include "fixture.h"
#include "plumb/error.h"

namespace plumb {
namespace {

const std::string kArm = testing::kSourceDir + "/tests/models/arm2.xml";

TEST(ModelEditTest, EverySupportedFieldComesBack) {
  if (!CanSaveEditedXml()) GTEST_SKIP() << "this MuJoCo has no mjSpec";
  testing::TempDir dir;
  Model model = Model::Load(kArm);
  Data d(model);
  std::vector<std::string> edits = {"dof_damping[elbow]=0.7",
                                    "dof_armature[shoulder]=0.09",
                                    "dof_frictionloss[elbow]=0.05",
                                    "jnt_stiffness[shoulder]=3",
                                    "body_mass[payload]=1.3",
                                    "body_ipos[payload][2]=0.01",
                                    "geom_friction[payload][0]=0.6",
                                    "actuator_gear[elbow][0]=2",
                                    "actuator_gainprm[shoulder][0]=1.5",
                                    "actuator_biasprm[shoulder][1]=-0.2"};
  std::vector<Path> paths;
  for (const std::string& e : edits) {
    Assignment a = ParseAssignment(model, e);
    WriteValues(model, d, a.path, a.values);
    paths.push_back(a.path);
  }
  SaveXmlWithParameters(kArm, model, paths, dir.File("edited.xml"));
  Model saved = Model::Load(dir.File("edited.xml"));
  Data s(saved);
  for (const std::string& e : edits) {
    Assignment a = ParseAssignment(saved, e);
    EXPECT_NEAR(ReadValue(saved, s, a.path), a.values[0], 1e-12) << e;
  }
  // the mass came back with the inertia the edit scaled, not one recomputed from the geom
  int b = mj_name2id(saved.get(), mjOBJ_BODY, "payload");
  for (int k = 0; k < 3; ++k) {
    EXPECT_NEAR(saved->body_inertia[3 * b + k], model->body_inertia[3 * b + k], 1e-12) << k;
  }
  // everything else as it was
  Model original = Model::Load(kArm);
  EXPECT_EQ(saved->dof_damping[0], original->dof_damping[0]);
  EXPECT_EQ(saved->body_mass[1], original->body_mass[1]);
}

TEST(ModelEditTest, WhatCannotBeSavedIsRefusedAndNothingIsWritten) {
  if (!CanSaveEditedXml()) {
    testing::TempDir dir;
    Model model = Model::Load(kArm);
    EXPECT_THROW(SaveXmlWithParameters(kArm, model, {}, dir.File("x.xml")), UnavailableError);
    EXPECT_FALSE(std::filesystem::exists(dir.File("x.xml")));
    return;
  }
  testing::TempDir dir;
  Model model = Model::Load(kArm);
  try {
    SaveXmlWithParameters(kArm, model, {ResolvePath(model, "opt.timestep")}, dir.File("x.xml"));
    FAIL();
  } catch (const ValueError& e) {
    EXPECT_NE(std::string(e.what()).find("-o cannot write opt.timestep"), std::string::npos)
        << e.what();
  }
  try {  // the upper arm's geom has no name
    SaveXmlWithParameters(kArm, model, {ResolvePath(model, "geom_friction[#0][0]")},
                          dir.File("x.xml"));
    FAIL();
  } catch (const ValueError& e) {
    EXPECT_NE(std::string(e.what()).find("without a name"), std::string::npos) << e.what();
  }
  EXPECT_FALSE(std::filesystem::exists(dir.File("x.xml")));
  EXPECT_THROW(SaveXmlWithParameters(kArm, model, {}, dir.File("no/such/dir/x.xml")), IoError);
}

}  // namespace
}  // namespace plumb
