#include "plumb/path.h"

#include <gtest/gtest.h>

#include <cmath>
#include <set>

#include "core/fields.h"
#include "fixture.h"
#include "plumb/error.h"

namespace plumb {
using internal::FieldInfo;
using internal::Fields;
using internal::FieldSource;

namespace {

using testing::kHumanoid;
using testing::kPendulum;
using testing::MujocoTest;

// A small robot with every kind of row the grammar names: a free base, a ball joint,
// a hinge, a motor, a sensor of dimension 3 and a mocap body.
constexpr char kRobot[] = R"(
<mujoco model="robot">
  <worldbody>
    <body name="mocap" mocap="true" pos="1 0 0"/>
    <body name="torso" pos="0 0 1">
      <freejoint name="root"/>
      <geom name="chest" type="box" size="0.1 0.1 0.1" mass="10"/>
      <site name="imu"/>
      <body name="arm" pos="0.2 0 0">
        <joint name="shoulder" type="ball"/>
        <geom name="upper" type="capsule" fromto="0 0 0 0.3 0 0" size="0.03"/>
        <body name="forearm" pos="0.3 0 0">
          <joint name="elbow" type="hinge" axis="0 1 0" damping="0.1"/>
          <geom name="foot" type="sphere" size="0.05" friction="0.8 0.01 0.001"/>
        </body>
      </body>
    </body>
  </worldbody>
  <actuator><motor name="motor" joint="elbow" gear="50"/></actuator>
  <sensor>
    <accelerometer name="imu_acc" site="imu"/>
    <jointpos name="elbow_angle" joint="elbow"/>
  </sensor>
</mujoco>)";

class PathTest : public MujocoTest {
 protected:
  Model robot_ = Model::FromXmlString(kRobot, "robot.xml");
  Data data_{robot_};
};

// MuJoCo 3.5+'s delays keep past controls in d->history: readable, and a write is refused
// with the reason (MuJoCo's own ring buffer), not as a derived quantity
TEST_F(PathTest, TheDelayHistoryIsReadOnlyAndSaysWhy) {
#if mjVERSION_HEADER >= 3005000
  Model model = Model::FromXmlString(R"(<mujoco><worldbody><body><joint name="j" axis="0 1 0"/>
      <geom type="capsule" fromto="0 0 0 0.3 0 0" size="0.03" mass="1"/></body></worldbody>
      <actuator><motor name="m" joint="j" delay="0.01" nsample="10"/></actuator></mujoco>)");
  Data data(model);
  Path history = ResolvePath(model, "history[0]");
  EXPECT_EQ(ReadValue(model, data, history, 0), data->history[0]);
  try {
    ApplyAssignments(model, data, {ParseAssignment(model, "history[0]=1")});
    FAIL() << "history was written";
  } catch (const PathError& e) {
    EXPECT_NE(std::string(e.what()).find("ring buffer"), std::string::npos) << e.what();
  }
#else
  GTEST_SKIP() << "delays came with MuJoCo 3.5";
#endif
}

TEST_F(PathTest, JointNamesMapToQposAndDofBlocks) {
  Path root = ResolvePath(robot_, "qpos[root]");
  EXPECT_EQ(root.first, 0);
  EXPECT_EQ(root.count, 7);
  Path z = ResolvePath(robot_, "qpos[root][2]");
  EXPECT_EQ(z.first, 2);
  EXPECT_EQ(z.count, 1);
  EXPECT_EQ(z.text, "qpos[root][2]");
  Path shoulder = ResolvePath(robot_, "qvel[shoulder]");
  EXPECT_EQ(shoulder.first, robot_->jnt_dofadr[1]);
  EXPECT_EQ(shoulder.count, 3);
  Path elbow = ResolvePath(robot_, "qpos[elbow]");
  EXPECT_EQ(elbow.first, robot_->jnt_qposadr[2]);
  EXPECT_EQ(elbow.count, 1);
  EXPECT_EQ(ResolvePath(robot_, "qpos[3]").first, 3);
  EXPECT_EQ(ResolvePath(robot_, "qpos").count, robot_->nq);
}

TEST_F(PathTest, ReadsWhatMujocoHolds) {
  data_->qpos[2] = 1.25;
  EXPECT_EQ(ReadValue(robot_, data_, ResolvePath(robot_, "qpos[root][2]")), 1.25);
  EXPECT_EQ(ReadValue(robot_, data_, ResolvePath(robot_, "time")), data_->time);
  data_.Forward();
  Path x = ResolvePath(robot_, "xpos[forearm][0]");
  int forearm = mj_name2id(robot_.get(), mjOBJ_BODY, "forearm");
  EXPECT_EQ(ReadValue(robot_, data_, x), data_->xpos[3 * forearm]);
  Path acc = ResolvePath(robot_, "sensordata[imu_acc][1]");
  EXPECT_EQ(acc.first, 1);
  EXPECT_EQ(ResolvePath(robot_, "sensordata[elbow_angle]").first, 3);
  EXPECT_EQ(ResolvePath(robot_, "ctrl[motor]").first, 0);
  EXPECT_EQ(ResolvePath(robot_, "mocap_pos[mocap][0]").first, 0);
}

// One rule for PATH=VALUE text, for --set, --vary and --randomize.
TEST_F(PathTest, AssignmentTextSplitsAtTheFirstEquals) {
  auto [path, value] = SplitAssignment("qpos[hinge]=0.7", "--set", "PATH=VALUE");
  EXPECT_EQ(path, "qpos[hinge]");
  EXPECT_EQ(value, "0.7");
  auto [p2, v2] = SplitAssignment("body_mass[*]=*U(0.9,1.1)", "--randomize", "PATH=DIST");
  EXPECT_EQ(p2, "body_mass[*]");
  EXPECT_EQ(v2, "*U(0.9,1.1)");
  try {
    SplitAssignment("qpos[hinge]", "--vary", "PATH=V1,V2");
    ADD_FAILURE() << "no error";
  } catch (const ValueError& e) {
    EXPECT_EQ(std::string(e.what()), "--vary 'qpos[hinge]': expected PATH=V1,V2.");
  }
}

// Parameters are written in order with body_inertia last; only model arrays (not options)
// ask for mj_setConst; state is written apart.
TEST_F(PathTest, ParametersAreWrittenInertiaLastAndSayWhenConstantsAreStale) {
  Model model = Model::Load(kPendulum);
  Data data(model);
  EXPECT_TRUE(ChangesModelArrays(ResolvePath(model, "body_mass[link]")));
  EXPECT_FALSE(ChangesModelArrays(ResolvePath(model, "opt.timestep")));
  std::vector<Assignment> sets = {ParseAssignment(model, "body_inertia[link]=1,2,2"),
                                  ParseAssignment(model, "body_mass[link]=2"),
                                  ParseAssignment(model, "qpos[hinge]=0.3")};
  EXPECT_TRUE(WriteParameters(model, data, sets));
  // the given inertia wins over the rescaling the new mass implies
  EXPECT_EQ(model->body_inertia[3], 1);
  EXPECT_EQ(model->body_mass[1], 2);
  EXPECT_EQ(data->qpos[0], 0);  // state untouched
  WriteState(model, data, sets);
  EXPECT_EQ(data->qpos[0], 0.3);
  EXPECT_FALSE(WriteParameters(model, data, {ParseAssignment(model, "opt.timestep=0.001")}));
}

TEST_F(PathTest, ModelParametersUseTheSameGrammar) {
  EXPECT_EQ(ReadValue(robot_, data_, ResolvePath(robot_, "dof_damping[elbow]")), 0.1);
  EXPECT_EQ(ReadValue(robot_, data_, ResolvePath(robot_, "body_mass[torso]")), 10);
  EXPECT_EQ(ReadValue(robot_, data_, ResolvePath(robot_, "geom_friction[foot][0]")), 0.8);
  EXPECT_EQ(ReadValue(robot_, data_, ResolvePath(robot_, "actuator_gear[motor][0]")), 50);
  EXPECT_EQ(ResolvePath(robot_, "opt.gravity").count, 3);
  EXPECT_EQ(ReadValue(robot_, data_, ResolvePath(robot_, "opt.gravity[2]")), -9.81);
  EXPECT_EQ(ReadValue(robot_, data_, ResolvePath(robot_, "opt.timestep")), 0.002);
  EXPECT_EQ(ResolvePath(robot_, "nq").role, Role::kParameter);
  EXPECT_FALSE(ResolvePath(robot_, "nq").writable);
}

TEST_F(PathTest, RolesFollowTheChaptersClassification) {
  EXPECT_EQ(ResolvePath(robot_, "qpos[elbow]").role, Role::kState);
  EXPECT_EQ(ResolvePath(robot_, "time").role, Role::kState);
  EXPECT_EQ(ResolvePath(robot_, "ctrl[motor]").role, Role::kInput);
  EXPECT_EQ(ResolvePath(robot_, "xpos[torso]").role, Role::kDerived);
  EXPECT_EQ(ResolvePath(robot_, "body_mass[torso]").role, Role::kParameter);
  EXPECT_STREQ(RoleName(Role::kDerived), "derived");
}

TEST_F(PathTest, EveryArrayOfTheXMacroTablesIsReachable) {
  // every numeric field with rows in this model (or a scalar) resolves and reads, but
  // those no sampled state computes, and constraint rows beyond nefc (0 here)
  const std::set<std::string> not_computed = {
      "qfrc_inverse", "qH",  "qHDiagInv", "D_rownnz",      "D_rowadr", "D_colind",
      "qDeriv",       "qLU", "efc_AR",    "efc_AR_colind", "efc_JT",   "efc_JT_colind"};
  int resolved = 0;
  for (const FieldInfo& field : Fields()) {
    if (field.type == compat::ElemType::kOther) continue;
    if (field.rows(robot_.get()) * field.cols(robot_.get()) == 0) continue;
    // (3.x keeps D_rownnz, D_rowadr and D_colind in mjModel too, where they are constants)
    if (field.source == FieldSource::kDataArray && not_computed.count(field.name)) {
      EXPECT_THROW(ResolvePath(robot_, field.name), PathError) << field.name;
      continue;
    }
    Path p = ResolvePath(robot_, field.name);
    if (field.current_rows && field.current_rows(robot_.get(), data_.get()) == 0) {
      // constraint, contact and island rows the state does not hold (nefc = 0 here)
      ASSERT_EQ(data_->nefc, 0);
      EXPECT_THROW(ReadValue(robot_, data_, p, p.count - 1), PathError) << field.name;
      continue;
    }
    if (field.current_rows) {
      p.count = field.current_rows(robot_.get(), data_.get()) * field.cols(robot_.get());
    }
    double v = ReadValue(robot_, data_, p, p.count - 1);
    EXPECT_FALSE(std::isnan(v) && field.type != compat::ElemType::kNum) << field.name;
    ++resolved;
  }
  EXPECT_GT(resolved, 150);
}

TEST_F(PathTest, UnknownNameListsTheNearest) {
  try {
    ResolvePath(robot_, "qpos[elbw]");
    FAIL();
  } catch (const PathError& e) {
    std::string what = e.what();
    EXPECT_NE(what.find("no joint named 'elbw'"), std::string::npos) << what;
    EXPECT_NE(what.find("did you mean: elbow"), std::string::npos) << what;
  }
}

TEST_F(PathTest, UnknownFieldListsTheNearest) {
  try {
    ResolvePath(robot_, "qpso[elbow]");
    FAIL();
  } catch (const PathError& e) {
    EXPECT_NE(std::string(e.what()).find("qpos"), std::string::npos) << e.what();
  }
  try {
    ResolvePath(robot_, "opt.timstep");
    FAIL();
  } catch (const PathError& e) {
    EXPECT_NE(std::string(e.what()).find("opt.timestep"), std::string::npos) << e.what();
  }
}

TEST_F(PathTest, OutOfBoundsIndicesAreRejected) {
  EXPECT_THROW(ResolvePath(robot_, "qpos[99]"), PathError);
  EXPECT_THROW(ResolvePath(robot_, "qpos[root][7]"), PathError);
  EXPECT_THROW(ResolvePath(robot_, "xpos[torso][3]"), PathError);
  EXPECT_THROW(ResolvePath(robot_, "opt.gravity[3]"), PathError);
  EXPECT_THROW(ResolvePath(robot_, "qpos[elbow"), PathError);
  EXPECT_THROW(ResolvePath(robot_, "qpos[a][0][1]"), PathError);
  EXPECT_THROW(ResolvePath(robot_, "qpos[*]"), PathError);  // only lists take '*'
}

TEST_F(PathTest, RowsWithoutThatKindOfEntryAreExplained) {
  // the motor has no activation state; torso is not a mocap body
  EXPECT_THROW(ResolvePath(robot_, "act[motor]"), PathError);
  EXPECT_THROW(ResolvePath(robot_, "mocap_pos[torso]"), PathError);
}

TEST_F(PathTest, AssignmentsParseVectorsAndEnumNames) {
  Assignment g = ParseAssignment(robot_, "opt.gravity=0,0,-1.62");
  EXPECT_EQ(g.values, (std::vector<double>{0, 0, -1.62}));
  Assignment rk4 = ParseAssignment(robot_, "opt.integrator=RK4");
  EXPECT_EQ(rk4.values[0], mjINT_RK4);
  EXPECT_EQ(ParseAssignment(robot_, "opt.integrator=implicit").values[0], mjINT_IMPLICIT);
  EXPECT_THROW(ParseAssignment(robot_, "opt.integrator=Verlet"), ValueError);
  Assignment ball = ParseAssignment(robot_, "qvel[shoulder]=0.5,0,0");
  EXPECT_EQ(ball.values, (std::vector<double>{0.5, 0, 0}));
}

// issue 9: 'qpos[root]=1' silently wrote all 7 entries of a free joint (and MuJoCo then
// normalised the quaternion), while 3 values were refused
TEST_F(PathTest, ABlockTakesExactlyAsManyValuesAsItHas) {
  for (const char* text : {"qpos[root]=1", "qpos[root]=0,0,1", "qvel[shoulder]=0.5"}) {
    try {
      ParseAssignment(robot_, text);
      ADD_FAILURE() << text << " was accepted";
    } catch (const ValueError& e) {
      std::string what = e.what();
      EXPECT_NE(what.find("give exactly"), std::string::npos) << what;
      EXPECT_NE(what.find("[0]="), std::string::npos) << what;  // how to set one element
    }
  }
  try {
    ParseAssignment(robot_, "qpos[root]=1");
  } catch (const ValueError& e) {
    EXPECT_NE(std::string(e.what()).find("a block of 7 values (a free joint"), std::string::npos)
        << e.what();
  }
  EXPECT_EQ(ParseAssignment(robot_, "qpos[root]=0,0,1,1,0,0,0").values.size(), 7u);
  EXPECT_TRUE(ParseAssignment(robot_, "qpos[root]=0,0,1,1,0,0,0").warnings.empty());
  // a quaternion MuJoCo will normalise is said to be
  std::vector<std::string> w = ParseAssignment(robot_, "qpos[root]=1,1,1,1,1,1,1").warnings;
  ASSERT_EQ(w.size(), 1u);
  EXPECT_NE(w[0].find("norm 2; MuJoCo normalises it"), std::string::npos) << w[0];
  Assignment z = ParseAssignment(robot_, "qpos[root][2]=1");
  ApplyAssignments(robot_, data_, {z});
  EXPECT_EQ(data_->qpos[2], 1);
  EXPECT_EQ(data_->qpos[3], 1);  // the quaternion is untouched
  EXPECT_EQ(data_->qpos[0], 0);
}

// issue 9: 'ctrl[slide]=5' beyond ctrlrange was clamped by MuJoCo without a word
TEST_F(PathTest, CtrlBeyondCtrlrangeWarnsWithTheRange) {
  Model model = Model::FromXmlString(R"(<mujoco><worldbody><body>
      <joint name="slider" type="slide"/><geom size="0.1" mass="1"/></body></worldbody>
      <actuator><motor name="slide" joint="slider" ctrlrange="-1 1" ctrllimited="true"/>
        <motor name="free" joint="slider"/></actuator></mujoco>)");
  Assignment beyond = ParseAssignment(model, "ctrl[slide]=5");
  ASSERT_EQ(beyond.warnings.size(), 1u);
  EXPECT_NE(beyond.warnings[0].find("ctrlrange [-1, 1] of actuator 'slide'"), std::string::npos)
      << beyond.warnings[0];
  EXPECT_NE(beyond.warnings[0].find("ctrl = 1"), std::string::npos) << beyond.warnings[0];
  EXPECT_TRUE(ParseAssignment(model, "ctrl[slide]=-1").warnings.empty());
  EXPECT_TRUE(ParseAssignment(model, "ctrl[free]=50").warnings.empty());  // not limited
  EXPECT_EQ(ParseAssignment(model, "ctrl=3,50").warnings.size(), 1u);
}

// issue 9: efc_force[200] was readable with nefc = 32 (MuJoCo allocates njmax rows)
TEST_F(PathTest, EfcForceBeyondNefcIsRefused) {
  Model model = Model::FromXmlString(R"(<mujoco><worldbody>
      <geom name="floor" type="plane" size="5 5 0.1"/>
      <body name="box" pos="0 0 0.09"><freejoint/><geom type="box" size="0.1 0.1 0.1"/></body>
    </worldbody></mujoco>)");
  Data data(model);
  data.Forward();
  int nefc = data->nefc;
  ASSERT_GT(nefc, 0);
  ASSERT_LT(nefc, 200);
  EXPECT_NO_THROW(
      ReadValue(model, data, ResolvePath(model, "efc_force[" + std::to_string(nefc - 1) + "]")));
  Path beyond = ResolvePath(model, "efc_force[200]");  // within njmax: resolves
  try {
    ReadValue(model, data, beyond);
    ADD_FAILURE() << "efc_force[200] read with nefc = " << nefc;
  } catch (const PathError& e) {
    EXPECT_NE(std::string(e.what()).find("nefc = " + std::to_string(nefc)), std::string::npos)
        << e.what();
  }
  // the whole array reads exactly nefc elements
  Path all = ResolvePath(model, "efc_force");
  EXPECT_NO_THROW(ReadValue(model, data, all, nefc - 1));
  EXPECT_THROW(ReadValue(model, data, all, nefc), PathError);
}

// issue 9: paths whose value no sampled state has computed read as 0
TEST_F(PathTest, FieldsMujocoDoesNotComputeAreRefused) {
  for (const char* text : {"qfrc_inverse[elbow]", "qH", "qLU", "qDeriv", "efc_AR[0][1]"}) {
    try {
      ResolvePath(robot_, text);
      ADD_FAILURE() << text << " resolved";
    } catch (const PathError& e) {
      EXPECT_NE(std::string(e.what()).find("cannot be read"), std::string::npos) << e.what();
    }
  }
}

// issue 9: scaling a body's mass left its inertia, giving a 1000 kg body the moments of 1 kg
TEST_F(PathTest, AMassEditScalesTheInertia) {
  int arm = mj_name2id(robot_.get(), mjOBJ_BODY, "arm");
  std::vector<double> before(robot_->body_inertia + 3 * arm, robot_->body_inertia + 3 * arm + 3);
  double ratio = 25 / robot_->body_mass[arm];
  ApplyAssignments(robot_, data_, {ParseAssignment(robot_, "body_mass[arm]=25")});
  for (int i = 0; i < 3; ++i) {
    EXPECT_NEAR(robot_->body_inertia[3 * arm + i], ratio * before[i], 1e-12 * ratio * before[i]);
  }
  // an inertia given with it wins, in either order
  Model again = Model::FromXmlString(kRobot, "robot.xml");
  Data data(again);
  ApplyAssignments(again, data,
                   {ParseAssignment(again, "body_inertia[arm]=0.1,0.2,0.25"),
                    ParseAssignment(again, "body_mass[arm]=100")});
  EXPECT_EQ(again->body_mass[arm], 100);
  EXPECT_EQ(again->body_inertia[3 * arm + 1], 0.2);
}

TEST_F(PathTest, BadValuesAreRejected) {
  EXPECT_THROW(ParseAssignment(robot_, "qpos[elbow]=abc"), ValueError);
  EXPECT_THROW(ParseAssignment(robot_, "qpos[elbow]=nan"), ValueError);
  EXPECT_THROW(ParseAssignment(robot_, "qpos[elbow]=inf"), ValueError);
  EXPECT_THROW(ParseAssignment(robot_, "qpos[elbow]"), ValueError);
  EXPECT_THROW(ParseAssignment(robot_, "opt.gravity=1,2"), ValueError);
  EXPECT_THROW(ParseAssignment(robot_, "opt.timestep=0"), ValueError);
  EXPECT_THROW(ParseAssignment(robot_, "opt.iterations=2.5"), ValueError);
  // values that parse but MuJoCo would misread: out-of-range enums, bad condim, bounds
  EXPECT_THROW(ParseAssignment(robot_, "opt.integrator=9"), ValueError);
  EXPECT_THROW(ParseAssignment(robot_, "opt.cone=-1"), ValueError);
  EXPECT_EQ(ParseAssignment(robot_, "opt.integrator=1").values[0], mjINT_RK4);
  EXPECT_THROW(ParseAssignment(robot_, "opt.iterations=-5"), ValueError);
  EXPECT_THROW(ParseAssignment(robot_, "opt.iterations=0"), ValueError);
  // one bit beyond the disable flags this MuJoCo has (13 on 2.2.2, 20 on 4.0.1)
  EXPECT_THROW(ParseAssignment(robot_, "opt.disableflags=" + std::to_string(1 << mjNDISABLE)),
               ValueError);
  EXPECT_THROW(ParseAssignment(robot_, "body_mass[torso]=-1"), ValueError);
  EXPECT_NO_THROW(ParseAssignment(robot_, "body_mass[torso]=0"));
  EXPECT_THROW(ParseAssignment(robot_, "geom_condim[foot]=7"), ValueError);
  EXPECT_NO_THROW(ParseAssignment(robot_, "geom_condim[foot]=6"));
  try {
    ParseAssignment(robot_, "opt.integrator=9");
  } catch (const ValueError& e) {
    EXPECT_NE(std::string(e.what()).find("RK4 (1)"), std::string::npos) << e.what();
  }
  // derived quantities and structure cannot be set
  EXPECT_THROW(ParseAssignment(robot_, "xpos[torso][2]=1"), PathError);
  EXPECT_THROW(ParseAssignment(robot_, "jnt_qposadr[elbow]=0"), PathError);
  EXPECT_THROW(ParseAssignment(robot_, "body_subtreemass[torso]=1"), PathError);
}

TEST_F(PathTest, NamesWithSpacesResolve) {
  // MJCF names are free text; blanks around a name and outside brackets are ignored
  Model model = Model::FromXmlString(R"(<mujoco><worldbody>
      <body name="pinch site" pos="0 0 1"><joint name="wrist hinge"/>
        <geom type="sphere" size="0.1" mass="2"/></body></worldbody></mujoco>)");
  EXPECT_EQ(ResolvePath(model, "body_mass[pinch site]").first, 1);
  EXPECT_EQ(ResolvePath(model, "body_mass[ pinch site ]").first, 1);
  EXPECT_EQ(ResolvePath(model, " xpos [pinch site] [2]").first,
            ResolvePath(model, "xpos[1][2]").first);
  EXPECT_EQ(ParseAssignment(model, "qpos[wrist hinge] = 0.3").values[0], 0.3);
  EXPECT_THROW(ResolvePath(model, "body_mass[pinchsite]"), PathError);
}

TEST_F(PathTest, MassEditsRecomputeDerivedConstants) {
  int torso = mj_name2id(robot_.get(), mjOBJ_BODY, "torso");
  double subtree_before = robot_->body_subtreemass[torso];
  ApplyAssignments(robot_, data_, {ParseAssignment(robot_, "body_mass[torso]=20")});
  EXPECT_EQ(robot_->body_mass[torso], 20);
  EXPECT_NEAR(robot_->body_subtreemass[torso], subtree_before + 10, 1e-12);
  EXPECT_NEAR(robot_->body_subtreemass[0], subtree_before + 10 + robot_->body_mass[1], 1e-12);
}

TEST_F(PathTest, ApplyAssignmentsSetsStateAfterParametersAndForwards) {
  ApplyAssignments(robot_, data_,
                   {ParseAssignment(robot_, "qpos[root][2]=3"),
                    ParseAssignment(robot_, "opt.gravity=0,0,-1.62")});
  EXPECT_EQ(robot_->opt.gravity[2], -1.62);
  EXPECT_EQ(data_->qpos[2], 3);
  // mj_forward ran: the derived body position agrees with the state
  EXPECT_EQ(data_->xpos[3 * 2 + 2], 3);
}

TEST_F(PathTest, StarExpandsEveryRowButTheWorld) {
  std::vector<Path> masses = ExpandPath(robot_, "body_mass[*]");
  ASSERT_EQ(masses.size(), 4u);  // mocap, torso, arm, forearm: not the world body
  EXPECT_EQ(masses[0].text, "body_mass[mocap]");
  EXPECT_EQ(masses[1].text, "body_mass[torso]");
  std::vector<Path> friction = ExpandPath(robot_, "geom_friction[*][0]");
  EXPECT_EQ(friction.size(), 3u);
  EXPECT_EQ(friction[2].count, 1);
  // unnamed objects are included, written by id, and that text resolves again
  Model anonymous = Model::FromXmlString(R"(<mujoco><worldbody>
      <body name="named"><freejoint/><geom size="0.1"/>
        <body pos="0.3 0 0"><joint axis="0 1 0"/><geom size="0.1"/></body></body>
    </worldbody></mujoco>)");
  std::vector<Path> all = ExpandPath(anonymous, "body_mass[*]");
  ASSERT_EQ(all.size(), 2u);
  EXPECT_EQ(all[1].text, "body_mass[#2]");
  EXPECT_EQ(ResolvePath(anonymous, "body_mass[#2]").first, 2);
  std::vector<Path> joints = ExpandPath(anonymous, "qpos[*]");
  ASSERT_EQ(joints.size(), 2u);
  EXPECT_EQ(joints[0].count, 7);  // the free joint's block
  EXPECT_EQ(joints[1].first, 7);  // the unnamed hinge's qpos address
}

TEST_F(PathTest, DefaultColumnsExpandBlocks) {
  std::vector<Path> columns = DefaultColumns(robot_);
  // time + qpos (7 + 4 + 1) + qvel (6 + 3 + 1) + ctrl (1) + sensordata (3 + 1)
  ASSERT_EQ(columns.size(), 1u + 12 + 10 + 1 + 4);
  EXPECT_EQ(columns[0].text, "time");
  EXPECT_EQ(columns[1].text, "qpos[root][0]");
  EXPECT_EQ(columns[12].text, "qpos[elbow]");
  EXPECT_EQ(columns[23].text, "ctrl[motor]");  // what drove the run, for replay
  EXPECT_EQ(columns.back().text, "sensordata[elbow_angle]");
}

TEST_F(PathTest, HumanoidNamesResolve) {
  Model humanoid = Model::Load(kHumanoid);
  EXPECT_EQ(ResolvePath(humanoid, "qpos[root]").count, 7);
  EXPECT_EQ(ResolvePath(humanoid, "qvel[root]").count, 6);
  EXPECT_EQ(ResolvePath(humanoid, "xpos[torso][2]").first,
            3 * mj_name2id(humanoid.get(), mjOBJ_BODY, "torso") + 2);
}

TEST_F(PathTest, PendulumHingeIsAScalar) {
  Model pendulum = Model::Load(kPendulum);
  Path hinge = ResolvePath(pendulum, "qpos[hinge]");
  EXPECT_EQ(hinge.first, 0);
  EXPECT_EQ(hinge.count, 1);
  EXPECT_EQ(ResolvePath(pendulum, "geom_size[rod][0]").count, 1);
}

// Flags could only be set as a whole bitmask (opt.enableflags=128 overwrote the other flags).
TEST_F(PathTest, AFlagIsSetByNameAndKeepsTheOtherFlags) {
  Model pendulum = Model::Load(kPendulum);
  Data data(pendulum);
  pendulum.get_mutable()->opt.disableflags = mjDSBL_CONTACT;
  Path gravity = ResolvePath(pendulum, "opt.disableflags.Gravity");
  EXPECT_EQ(gravity.text, "opt.disableflags.gravity");
  EXPECT_EQ(ReadValue(pendulum, data, gravity), 0);
  WriteValues(pendulum, data, gravity, {1});
  EXPECT_EQ(pendulum->opt.disableflags, mjDSBL_CONTACT | mjDSBL_GRAVITY);
  EXPECT_EQ(ReadValue(pendulum, data, gravity), 1);
  WriteValues(pendulum, data, ResolvePath(pendulum, "opt.disableflags.contact"), {0});
  EXPECT_EQ(pendulum->opt.disableflags, mjDSBL_GRAVITY);
  // one flag takes 0 or 1; an unknown flag gets the nearest names and the list
  EXPECT_THROW(WriteValues(pendulum, data, gravity, {2}), ValueError);
  try {
    ResolvePath(pendulum, "opt.enableflags.enrgy");
    ADD_FAILURE() << "an unknown flag resolved";
  } catch (const PathError& e) {
    std::string message = e.what();
    EXPECT_NE(message.find("'enrgy' is not a flag of opt.enableflags"), std::string::npos)
        << message;
    EXPECT_NE(message.find("did you mean: energy"), std::string::npos) << message;
  }
  EXPECT_THROW(ResolvePath(pendulum, "opt.enableflags.energy[0]"), PathError);
}

// Found by tests/hostile/hostile_models.py: MuJoCo compiles "nan" and "inf" with at most a
// warning, and verify's load check and audit passed such a model.
TEST_F(PathTest, NonFiniteParametersAreNamedByPath) {
  Model model = Model::FromXmlString(testing::kNonFiniteXml, "nan.xml");
  TakeMujocoWarnings();
  NonFiniteValues bad = NonFiniteParameters(model);
  EXPECT_EQ(bad.total, 2);
  ASSERT_EQ(bad.first.size(), 2u);
  EXPECT_EQ(bad.first[0], "dof_damping[hinge] = nan");
  EXPECT_EQ(bad.first[1], "geom_rgba[rod][1] = inf");
  EXPECT_EQ(NonFiniteParameters(model, 1).first.size(), 1u);
  EXPECT_EQ(NonFiniteParameters(Model::Load(testing::kPendulum)).total, 0);
}

// Regression (the fuzzer, fuzz_paths): a whole constraint array of the humanoid, sized by
// MuJoCo's arena, split into one path per element took over 2 GB.
TEST(ScalarPathsTest, AHugeBlockIsRefusedNamingIt) {
  Model model = Model::Load(testing::kHumanoid);
  Path block = ResolvePath(model, "efc_AR_rownnz");
  if (block.count <= kMostScalarPaths) GTEST_SKIP() << "efc rows: " << block.count;
  try {
    ScalarPaths(block);
    FAIL() << "no error";
  } catch (const PathError& e) {
    EXPECT_NE(std::string(e.what()).find("'efc_AR_rownnz' holds"), std::string::npos) << e.what();
  }
  EXPECT_EQ(ScalarPaths(ResolvePath(model, "qpos")).size(), static_cast<size_t>(model->nq));
}

}  // namespace
}  // namespace plumb
