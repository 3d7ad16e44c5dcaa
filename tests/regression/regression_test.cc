#include "plumb/regression.h"

#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include "corpus_robots.h"
#include "fixture.h"
#include "keyed_model.h"
#include "plumb/error.h"
#include "plumb/result_table.h"

namespace plumb {
namespace {

std::string Changes(const SnapshotDiff& d) {
  std::string out;
  for (const SnapshotChange& c : d.changes) out += c.what + "\n";
  return out;
}

class RegressionTest : public testing::MujocoTest {
 protected:
  Model pendulum_ = Model::Load(testing::kPendulum);
  std::string snapshot_ = MakeSnapshot(pendulum_, {});
};

TEST_F(RegressionTest, UnchangedModelIsIdentical) {
  SnapshotDiff d = DiffSnapshot(snapshot_, pendulum_, {}, 1e-6);
  EXPECT_FALSE(d.changed()) << Changes(d);
  EXPECT_TRUE(d.notes.empty());
  EXPECT_EQ(MakeSnapshot(pendulum_, {}), snapshot_);  // stable, byte for byte
}

TEST_F(RegressionTest, SnapshotRecordsWhatARegressionShouldNotice) {
  nlohmann::json j = nlohmann::json::parse(snapshot_);
  EXPECT_EQ(j["mujoco_version"], MujocoVersion());
  EXPECT_EQ(j["options"]["opt.timestep"], 0.002);
  EXPECT_EQ(j["structure"]["body"]["link"]["body_mass"], 1.0);
  EXPECT_EQ(j["structure"]["body"]["link"]["body_parentid"], "world");
  EXPECT_EQ(j["structure"]["joint"]["hinge"]["jnt_qposadr"], 0);
  EXPECT_EQ(j["structure"]["dof"]["hinge"]["dof_damping"], 0.05);
  EXPECT_EQ(j["structure"]["geom"]["rod"]["geom_size"][0], 0.05);
  EXPECT_EQ(j["trajectory"]["qpos"].size(), static_cast<std::size_t>(kSnapshotSteps));
}

// The golden trajectory starts at the reference pose every command shares (keyframe "home",
// else "test", else qpos0), as audit's layers do.
TEST_F(RegressionTest, TheTrajectoryStartsAtTheSharedReferencePose) {
  Model test = Model::FromXmlString(R"(<mujoco><option gravity="0 0 0"/><worldbody><body>
      <joint name="s" type="slide"/>
      <geom type="box" size="0.1 0.1 0.1" mass="1"/></body></worldbody>
      <keyframe><key name="test" qpos="1"/></keyframe></mujoco>)",
                                    "test.xml");
  nlohmann::json j = nlohmann::json::parse(MakeSnapshot(test, {}));
  EXPECT_EQ(j["trajectory"]["start"], "keyframe test");
  // no gravity, no force: it stays at 1
  EXPECT_EQ(j["trajectory"]["qpos"][0][0], 1.0);
  nlohmann::json pendulum = nlohmann::json::parse(snapshot_);
  EXPECT_EQ(pendulum["trajectory"]["start"], "qpos0");
}

TEST_F(RegressionTest, ChangedDampingIsNamedInMujocosWords) {
  SnapshotDiff d = DiffSnapshot(snapshot_, pendulum_,
                                {ParseAssignment(pendulum_, "dof_damping[hinge]=0.1")}, 1e-6);
  ASSERT_TRUE(d.changed());
  EXPECT_EQ(d.changes[0].what, "dof_damping[hinge]: 0.05 → 0.1");
}

TEST_F(RegressionTest, ChangesCarryPathOldNewAndKind) {
  SnapshotDiff d = DiffSnapshot(snapshot_, pendulum_,
                                {ParseAssignment(pendulum_, "dof_damping[hinge]=0.1"),
                                 ParseAssignment(pendulum_, "opt.timestep=0.001")},
                                1e-6);
  auto find = [&](const std::string& path) -> const SnapshotChange* {
    for (const SnapshotChange& c : d.changes) {
      if (c.path == path) return &c;
    }
    return nullptr;
  };
  const SnapshotChange* damping = find("dof_damping[hinge]");
  ASSERT_NE(damping, nullptr) << Changes(d);
  EXPECT_EQ(damping->kind, "parameter");
  EXPECT_EQ(damping->old_value, "0.05");
  EXPECT_EQ(damping->new_value, "0.1");
  const SnapshotChange* timestep = find("opt.timestep");
  ASSERT_NE(timestep, nullptr) << Changes(d);
  EXPECT_EQ(timestep->kind, "option");
  EXPECT_EQ(timestep->old_value, "0.002");
  EXPECT_EQ(timestep->new_value, "0.001");
}

TEST_F(RegressionTest, SnapshotTakenWithSetIsIdenticalToTheSameModel) {
  std::vector<Assignment> start = {ParseAssignment(pendulum_, "qpos[hinge]=0.7"),
                                   ParseAssignment(pendulum_, "dof_damping[hinge]=0.2")};
  std::string moving = MakeSnapshot(pendulum_, start);
  nlohmann::json j = nlohmann::json::parse(moving);
  EXPECT_EQ(j["sets"], nlohmann::json({"qpos[hinge]=0.7", "dof_damping[hinge]=0.2"}));
  SnapshotDiff d = DiffSnapshot(moving, pendulum_, {}, 1e-9);
  EXPECT_FALSE(d.changed()) << Changes(d);
  EXPECT_EQ(d.sets, std::vector<std::string>({"qpos[hinge]=0.7", "dof_damping[hinge]=0.2"}));
  EXPECT_TRUE(d.notes.empty());  // the assignments are d.sets, which the writers show
  EXPECT_NE(DiffTable(d, "p.json").find("snapshot's 'qpos[hinge]=0.7', 'dof_damping[hinge]=0.2'"),
            std::string::npos)
      << DiffTable(d, "p.json");
  // the caller's --set comes after the snapshot's and wins
  SnapshotDiff edited =
      DiffSnapshot(moving, pendulum_, {ParseAssignment(pendulum_, "dof_damping[hinge]=0.3")}, 1e-9);
  ASSERT_TRUE(edited.changed());
  EXPECT_EQ(edited.changes[0].what, "dof_damping[hinge]: 0.2 → 0.3");
}

TEST_F(RegressionTest, SnapshotWithoutRecordedSetsStillLoads) {
  // snapshots written before the --set values were recorded have no "sets" entry
  nlohmann::ordered_json j = nlohmann::ordered_json::parse(snapshot_);
  j.erase("sets");
  SnapshotDiff d = DiffSnapshot(j.dump(2), pendulum_, {}, 1e-6);
  EXPECT_FALSE(d.changed()) << Changes(d);
  EXPECT_TRUE(d.sets.empty());
}

// Keyframes are part of the structure (format 2): a changed "home" is named as such, not
// only seen as a trajectory that departs at step 1
TEST_F(RegressionTest, AChangedKeyframeIsNamed) {
  Model keyed = Model::FromXmlString(testing::kKeyed, "keyed.xml");
  std::string snapshot = MakeSnapshot(keyed, {});
  EXPECT_EQ(nlohmann::json::parse(snapshot)["plumb_snapshot"], 2);
  SnapshotDiff d =
      DiffSnapshot(snapshot, keyed, {ParseAssignment(keyed, "key_qpos[home]=0.6")}, 1e-6);
  ASSERT_TRUE(d.changed());
  EXPECT_EQ(d.changes[0].what, "key_qpos[home]: 0.5 → 0.6") << Changes(d);
  EXPECT_EQ(d.changes[0].kind, "parameter");
}

// A format-1 snapshot (before keyframes) still loads, says its keyframes are not compared,
// and a format from a newer plumb is refused with its number
TEST_F(RegressionTest, OlderFormatsLoadAndNewerOnesAreRefused) {
  Model keyed = Model::FromXmlString(testing::kKeyed, "keyed.xml");
  nlohmann::ordered_json j = nlohmann::ordered_json::parse(MakeSnapshot(keyed, {}));
  j["plumb_snapshot"] = 1;
  j["structure"].erase("keyframe");
  SnapshotDiff d = DiffSnapshot(j.dump(2), keyed, {}, 1e-6);
  EXPECT_FALSE(d.changed()) << Changes(d);
  ASSERT_EQ(d.notes.size(), 1u);
  EXPECT_NE(d.notes[0].find("predates keyframes"), std::string::npos) << d.notes[0];
  j["plumb_snapshot"] = 3;
  try {
    DiffSnapshot(j.dump(2), keyed, {}, 1e-6);
    FAIL() << "format 3 was read";
  } catch (const ValueError& e) {
    EXPECT_NE(std::string(e.what()).find("version 3 is not one this plumb reads (1 to 2)"),
              std::string::npos)
        << e.what();
  }
}

TEST_F(RegressionTest, RecordedSetTheModelRefusesIsAChange) {
  nlohmann::ordered_json j = nlohmann::ordered_json::parse(snapshot_);
  j["sets"] = {"qpos[gone]=1"};
  SnapshotDiff d = DiffSnapshot(j.dump(2), pendulum_, {}, 1e-6);
  ASSERT_EQ(d.changes.size(), 1u) << Changes(d);
  EXPECT_EQ(d.changes[0].kind, "set");
  EXPECT_EQ(d.changes[0].path, "qpos[gone]=1");
  EXPECT_NE(d.changes[0].what.find("does not apply to the current model"), std::string::npos)
      << d.changes[0].what;
  j["sets"] = {1};
  EXPECT_THROW(DiffSnapshot(j.dump(2), pendulum_, {}, 1e-6), ValueError);
}

TEST_F(RegressionTest, TrajectoryDepartureNamesTheStep) {
  // start away from rest so the trajectory moves, then nudge gravity slightly
  std::vector<Assignment> start = {ParseAssignment(pendulum_, "qpos[hinge]=0.7")};
  std::string moving = MakeSnapshot(pendulum_, start);
  start.push_back(ParseAssignment(pendulum_, "opt.gravity[2]=-9.8100001"));
  SnapshotDiff d = DiffSnapshot(moving, pendulum_, start, 1e-9);
  std::string all = Changes(d);
  EXPECT_NE(all.find("opt.gravity"), std::string::npos) << all;
  EXPECT_NE(all.find("trajectory departs at step "), std::string::npos) << all;
  EXPECT_NE(all.find("(joint 'hinge')"), std::string::npos) << all;
  const SnapshotChange& departs = d.changes.back();
  EXPECT_EQ(departs.kind, "trajectory");
  EXPECT_GT(departs.step, 0);
  EXPECT_EQ(departs.path.rfind("trajectory.q", 0), 0u) << departs.path;
  EXPECT_NE(all.find("(tol 1e-09)"), std::string::npos) << all;
  // below the tolerance it is the same model
  EXPECT_FALSE(DiffSnapshot(moving, pendulum_, start, 1e-6).changed());
}

TEST_F(RegressionTest, AddedAndRemovedElementsAreNamed) {
  Model two = Model::FromXmlString(R"(<mujoco model="pendulum"><option timestep="0.002"/>
    <worldbody><body name="link" pos="0 0 1.5">
      <joint name="hinge" type="hinge" axis="0 1 0" damping="0.05"/>
      <geom name="rod" type="capsule" fromto="0 0 0 0 0 -1" size="0.05" mass="1"/>
      <body name="gripper_left" pos="0 0 -1"><geom name="finger" type="sphere" size="0.02"/></body>
    </body></worldbody></mujoco>)");
  SnapshotDiff d = DiffSnapshot(snapshot_, two, {}, 1e-6);
  std::string all = Changes(d);
  EXPECT_NE(all.find("body added: gripper_left"), std::string::npos) << all;
  EXPECT_NE(all.find("geom added: finger"), std::string::npos) << all;
  EXPECT_NE(all.find("nbody: 2 → 3"), std::string::npos) << all;
  SnapshotDiff back = DiffSnapshot(MakeSnapshot(two, {}), pendulum_, {}, 1e-6);
  EXPECT_NE(Changes(back).find("body removed: gripper_left"), std::string::npos);
}

TEST_F(RegressionTest, EnumeratedOptionsAreNamed) {
  SnapshotDiff d =
      DiffSnapshot(snapshot_, pendulum_, {ParseAssignment(pendulum_, "opt.cone=elliptic")}, 1e-6);
  EXPECT_NE(Changes(d).find("opt.cone: pyramidal → elliptic"), std::string::npos) << Changes(d);
}

TEST_F(RegressionTest, DivergingTrajectorySaysWhere) {
  Model stiff = Model::FromXmlString(R"(<mujoco><option timestep="0.01" gravity="0 0 0"/>
    <worldbody><body><joint name="slider" type="slide" axis="1 0 0" stiffness="1e6"/>
    <geom type="sphere" size="0.05" mass="1"/></body></worldbody></mujoco>)");
  std::string snap = MakeSnapshot(stiff, {});
  SnapshotDiff d = DiffSnapshot(snap, stiff, {ParseAssignment(stiff, "qpos[slider]=0.01")}, 1e-6);
  TakeMujocoWarnings();
  EXPECT_TRUE(d.diverged);
  EXPECT_NE(Changes(d).find("diverges on the current model: the simulation diverged at t = "),
            std::string::npos)
      << Changes(d);
}

TEST_F(RegressionTest, SmallParametersChangeRelatively) {
  // 1e-8 -> 2e-8 is a doubling: an absolute floor of 1 would hide it
  std::vector<Assignment> tiny = {ParseAssignment(pendulum_, "dof_damping[hinge]=1e-8")};
  std::string snap = MakeSnapshot(pendulum_, tiny);
  SnapshotDiff d =
      DiffSnapshot(snap, pendulum_, {ParseAssignment(pendulum_, "dof_damping[hinge]=2e-8")}, 1e-6);
  EXPECT_NE(Changes(d).find("dof_damping[hinge]: 1e-08 → 2e-08"), std::string::npos) << Changes(d);
}

TEST_F(RegressionTest, SnapshotRecordsElementIds) {
  nlohmann::json j = nlohmann::json::parse(snapshot_);
  EXPECT_EQ(j["structure"]["body"]["world"]["id"], 0);
  EXPECT_EQ(j["structure"]["body"]["link"]["id"], 1);
  EXPECT_EQ(j["structure"]["joint"]["hinge"]["id"], 0);
}

TEST_F(RegressionTest, DivergingModelReportsItsDivergence) {
  Model stiff = Model::FromXmlString(R"(<mujoco><option timestep="0.01" gravity="0 0 0"/>
    <worldbody><body><joint name="slider" type="slide" axis="1 0 0" stiffness="1e6" ref="0.01"/>
    <geom type="sphere" size="0.05" mass="1"/></body></worldbody></mujoco>)");
  std::string divergence;
  MakeSnapshot(stiff, {}, &divergence);
  TakeMujocoWarnings();
  EXPECT_NE(divergence.find("joint 'slider'"), std::string::npos) << divergence;
  MakeSnapshot(pendulum_, {}, &divergence);
  EXPECT_EQ(divergence, "");
}

// The message DiffSnapshot throws for `text`.
std::string DamageMessage(const Model& model, const std::string& text) {
  try {
    DiffSnapshot(text, model, {}, 1e-6);
  } catch (const ValueError& e) {
    return e.what();
  }
  return "(no error)";
}

TEST_F(RegressionTest, DamagedSnapshotsNameTheEntry) {
  nlohmann::ordered_json good = nlohmann::ordered_json::parse(snapshot_);
  auto damaged = [&](auto edit) {
    nlohmann::ordered_json j = good;
    edit(j);
    return DamageMessage(pendulum_, j.dump());
  };
  std::string mass =
      damaged([](auto& j) { j["structure"]["body"]["link"]["body_mass"] = "heavy"; });
  EXPECT_NE(mass.find("structure.body.link.body_mass: expected a number, got \"heavy\""),
            std::string::npos)
      << mass;
  std::string size = damaged([](auto& j) { j["structure"]["geom"]["rod"]["geom_size"] = {0.05}; });
  EXPECT_NE(size.find("structure.geom.rod.geom_size: expected an array of 3 numbers"),
            std::string::npos)
      << size;
  std::string row = damaged([](auto& j) { j["trajectory"]["qpos"][3] = {1, 2}; });
  EXPECT_NE(row.find("trajectory.qpos[3]: expected an array of 1 numbers (sizes.nq)"),
            std::string::npos)
      << row;
  std::string missing = damaged([](auto& j) { j.erase("trajectory"); });
  EXPECT_NE(missing.find("trajectory: missing"), std::string::npos) << missing;
  std::string sizes = damaged([](auto& j) { j["sizes"] = 3; });
  EXPECT_NE(sizes.find("sizes: expected an object"), std::string::npos) << sizes;
  std::string steps = damaged([](auto& j) { j["trajectory"]["qvel"].erase(0); });
  EXPECT_NE(steps.find("different numbers of steps"), std::string::npos) << steps;
  std::string cell = damaged([](auto& j) { j["trajectory"]["act"] = "none"; });
  EXPECT_NE(cell.find("trajectory.act: expected an array of steps"), std::string::npos) << cell;
}

TEST_F(RegressionTest, NotASnapshotIsAValueError) {
  EXPECT_THROW(DiffSnapshot("{not json", pendulum_, {}, 1e-6), ValueError);
  EXPECT_THROW(DiffSnapshot("{\"a\": 1}", pendulum_, {}, 1e-6), ValueError);
}

TEST_F(RegressionTest, HumanoidMassChangeShowsInStructureAndTrajectory) {
  Model humanoid = Model::Load(testing::kHumanoid);
  std::string snap = MakeSnapshot(humanoid, {});
  SnapshotDiff d =
      DiffSnapshot(snap, humanoid, {ParseAssignment(humanoid, "body_mass[torso]=6")}, 1e-6);
  std::string all = Changes(d);
  EXPECT_NE(all.find("body_mass[torso]: 5.853834311 → 6"), std::string::npos) << all;
  EXPECT_NE(all.find("trajectory departs at step 2"), std::string::npos) << all;
}

// mjlab's G1 leaves most collision geoms unnamed: a change to one names the geom by its body,
// not by "#12" alone (the machine path keeps the key).
TEST_F(RegressionTest, AnUnnamedGeomIsNamedByItsBody) {
  std::string g1 = testing::RequireCorpusModel(testing::robots::kG1);
  if (g1.empty()) GTEST_SKIP() << "no robot corpus (make corpus)";
  Model model = Model::Load(g1);
  ASSERT_EQ(model.Name(mjOBJ_GEOM, 12), "");
  std::string snapshot = MakeSnapshot(model, {});
  SnapshotDiff d = DiffSnapshot(
      snapshot, model, {ParseAssignment(model, "geom_friction[#12]=0.5,0.005,0.0001")}, 1e-6);
  ASSERT_EQ(d.changes.size(), 1u) << Changes(d);
  EXPECT_EQ(d.changes[0].path, "geom_friction[#12]");
  EXPECT_NE(d.changes[0].what.find("(geom #12 of body 'left_ankle_roll_link')"), std::string::npos)
      << d.changes[0].what;
}

}  // namespace
}  // namespace plumb
