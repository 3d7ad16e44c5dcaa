// The crosscheck's own logic, without an engine: the model edits that make the engine's model
// plumb's, the stage comparison (matching contacts by geom pair, naming the first stage that
// disagrees), and the setup's errors.

#include "crosscheck/stage_compare.h"
#include "crosscheck/statistics_check.h"

#include <gtest/gtest.h>

#include <cstring>

#include "core/fields.h"
#include "crosscheck/engine_session.h"
#include "fixture.h"
#include "plumb/crosscheck.h"
#include "plumb/path.h"

namespace plumb {
using internal::ApplyEdits;
using internal::CompareStages;
using internal::CpuStages;
using internal::FieldValues;
using internal::ModelEdits;
using internal::StageContact;
using internal::StageNames;
using internal::StageValues;
using internal::JudgeIdenticalWorlds;
using internal::WorldsAreIdentical;

namespace {

using testing::kSourceDir;

const std::string kBox = kSourceDir + "/tests/models/crosscheck/box_on_plane.xml";

// States along CPU MuJoCo's run of `model` at the given steps.
std::vector<Data> States(const Model& model, const std::vector<long>& steps) {
  std::vector<Data> out;
  Data d(model);
  long step = 0;
  for (long want : steps) {
    while (step < want) mj_step(model.get(), d.get()), ++step;
    out.push_back(d.Clone());
  }
  return out;
}

std::vector<const mjData*> Pointers(const std::vector<Data>& states) {
  std::vector<const mjData*> out;
  for (const Data& d : states) out.push_back(d.get());
  return out;
}

const CheckRow& Row(const std::vector<CheckRow>& rows, const std::string& id) {
  for (const CheckRow& r : rows) {
    if (r.id == id) return r;
  }
  static CheckRow none;
  ADD_FAILURE() << "no row " << id;
  return none;
}

TEST(ModelEditsTest, EveryChangedElementGoesOverAndMakesTheSameModel) {
  Model base = Model::Load(testing::kPendulum);
  Model edited = base.Clone();
  Data data(edited);
  ApplyAssignments(
      edited, data,
      {ParseAssignment(edited, "body_mass[link]=2"), ParseAssignment(edited, "opt.timestep=0.001"),
       ParseAssignment(edited, "opt.gravity=0,0,-1.62")});
  nlohmann::json edits = ModelEdits(base, edited);
  auto has = [&](const std::string& field, long index, double value) {
    for (const auto& e : edits) {
      if (e[0] == field && e[1] == index && e[2].get<double>() == value) return true;
    }
    return false;
  };
  EXPECT_TRUE(has("body_mass", 1, 2)) << edits.dump();
  EXPECT_TRUE(has("opt.timestep", 0, 0.001)) << edits.dump();
  EXPECT_TRUE(has("opt.gravity", 2, -1.62)) << edits.dump();
  // what MuJoCo derived from the new mass goes over too (mj_setConst: subtree mass, inertia)
  bool derived = false;
  for (const auto& e : edits) derived = derived || e[0] == "body_subtreemass";
  EXPECT_TRUE(derived) << edits.dump();
  // applied to the file freshly compiled, the edits make plumb's model, bit for bit
  Model fresh = Model::Load(testing::kPendulum);
  ApplyEdits(edits, fresh);
  EXPECT_TRUE(ModelEdits(fresh, edited).empty()) << ModelEdits(fresh, edited).dump();
  EXPECT_TRUE(ModelEdits(base, base).empty());
  EXPECT_EQ(FieldValues(fresh, "opt.gravity")[2], -1.62);
}

TEST(StageCompareTest, IdenticalValuesPassEveryStageThatHasSomethingToCompare) {
  Model model = Model::Load(kBox);
  std::vector<Data> states = States(model, {30, 60, 90, 120});
  StageValues cpu = CpuStages(model, Pointers(states));
  ASSERT_EQ(cpu.contacts.size(), 16u);  // four corners in each of four states
  std::vector<CheckRow> rows = CompareStages(model, cpu, cpu, {0.06, 0.12, 0.18, 0.24});
  ASSERT_EQ(rows.size(), StageNames().size());
  for (const CheckRow& r : rows) {
    if (r.id == "stages.sensors") {
      EXPECT_EQ(r.status, CheckStatus::kSkip);  // the box has none
      continue;
    }
    EXPECT_EQ(r.status, CheckStatus::kPass) << r.id << ": " << r.explanation;
  }
}

TEST(StageCompareTest, AMissingContactIsTheFindingNamedByGeomPairAndLaterStagesFollow) {
  Model model = Model::Load(kBox);
  std::vector<Data> states = States(model, {30, 60});
  StageValues cpu = CpuStages(model, Pointers(states));
  StageValues engine = cpu;
  engine.contacts.erase(engine.contacts.begin());  // world 0 loses a corner
  engine.qacc[2] += 1;                             // and so accelerates differently
  std::vector<CheckRow> rows = CompareStages(model, cpu, engine, {0.06, 0.12});
  EXPECT_EQ(Row(rows, "stages.kinematics").status, CheckStatus::kPass);
  const CheckRow& contacts = Row(rows, "stages.contacts");
  EXPECT_EQ(contacts.status, CheckStatus::kFail);
  EXPECT_EQ(contacts.subject, "geom 'floor' (id 0) / geom 'box' (id 1)");
  EXPECT_NE(contacts.measured_text.find("4 contact(s) on CPU MuJoCo, 3 on the engine"),
            std::string::npos)
      << contacts.measured_text;
  EXPECT_NE(contacts.measured_text.find("t = 0.06 s"), std::string::npos);
  const CheckRow& acc = Row(rows, "stages.accelerations");
  EXPECT_EQ(acc.status, CheckStatus::kWarn);
  EXPECT_NE(acc.explanation.find("downstream of the contacts stage"), std::string::npos);
  EXPECT_EQ(acc.element.name, "box");
}

TEST(StageCompareTest, AContactAtTheEdgeOfDetectionIsRoundingNotADifference) {
  Model model = Model::Load(kBox);
  std::vector<Data> states = States(model, {60});
  StageValues cpu = CpuStages(model, Pointers(states));
  StageContact edge = cpu.contacts[0];
  edge.dist = model->geom_margin[edge.geom1];  // exactly where detection stops
  edge.pos[0] += 0.5;                          // far from every other contact
  StageValues engine = cpu;
  cpu.contacts.push_back(edge);
  std::vector<CheckRow> rows = CompareStages(model, cpu, engine, {0.12});
  EXPECT_EQ(Row(rows, "stages.contacts").status, CheckStatus::kPass);
}

TEST(StageCompareTest, KinematicsBeyondFloat32RoundingNamesTheBody) {
  Model model = Model::Load(kBox);
  std::vector<Data> states = States(model, {0, 60});
  StageValues cpu = CpuStages(model, Pointers(states));
  StageValues engine = cpu;
  engine.xpos[(1 * model->nbody + 1) * 3 + 2] += 1e-4;  // the box, second state, z
  std::vector<CheckRow> rows = CompareStages(model, cpu, engine, {0, 0.12});
  const CheckRow& kin = Row(rows, "stages.kinematics");
  EXPECT_EQ(kin.status, CheckStatus::kFail);
  EXPECT_EQ(ElementLabel(kin.element), "body 'box' (id 1)");
  EXPECT_NEAR(kin.measured.value, 1e-4, 1e-9);
  EXPECT_LT(kin.reference.value, 1e-4);
  // one float32 rounding of the position is not a difference
  engine = cpu;
  engine.xpos[(1 * model->nbody + 1) * 3 + 2] =
      static_cast<float>(engine.xpos[(1 * model->nbody + 1) * 3 + 2]);
  EXPECT_EQ(Row(CompareStages(model, cpu, engine, {0, 0.12}), "stages.kinematics").status,
            CheckStatus::kPass);
}

TEST(CrosscheckSetupTest, BadOptionsAndAMissingEnvironmentSayWhatToDo) {
  Model model = Model::Load(testing::kPendulum);
  CrosscheckOptions options;
  options.engine = "physx";
  try {
    Crosscheck(model, options);
    FAIL() << "an unknown engine was taken";
  } catch (const ArgumentError& e) {
    EXPECT_EQ(e.argument(), "engine");
    EXPECT_NE(std::string(e.what()).find("warp and mjx"), std::string::npos);
  }
  options.engine = "warp";
  options.checks = {"stages", "chaos"};
  EXPECT_THROW(Crosscheck(model, options), ArgumentError);
  options.checks = {"stages"};
  options.setup.python = "/nonexistent/bin/python";
  options.setup.adapter = kSourceDir + "/engines/adapter.py";
  try {
    Crosscheck(model, options);
    FAIL() << "a missing python was taken";
  } catch (const UnavailableError& e) {
    EXPECT_NE(std::string(e.what()).find("plumb crosscheck --setup --engine warp"),
              std::string::npos)
        << e.what();
  }
  EXPECT_THROW(FindEngineSetup("physx"), ArgumentError);
  EngineSetup warp = FindEngineSetup("warp");
  EXPECT_NE(warp.python.find("/warp-"), std::string::npos) << warp.python;  // warp-HASH/bin/python
  EXPECT_TRUE(std::filesystem::exists(warp.adapter)) << warp.adapter;
}

// The statistics of identical worlds (nothing randomized, no control noise) are no test of the
// distribution: their PASS is a SKIP that says so and how to vary them; a FAIL stays.
TEST(StatisticsCheckTest, IdenticalWorldsSkipTheirPassAndSayHowToVaryThem) {
  Model model = Model::Load(testing::kPendulum);
  CrosscheckOptions o;
  o.worlds = 32;
  EXPECT_TRUE(WorldsAreIdentical(o));
  CheckRow row;
  row.id = "statistics";
  row.status = CheckStatus::kPass;
  JudgeIdenticalWorlds(o, &row);
  EXPECT_EQ(row.status, CheckStatus::kSkip);
  EXPECT_NE(row.explanation.find("the 32 worlds are identical"), std::string::npos)
      << row.explanation;
  EXPECT_NE(row.fix.find("randomize"), std::string::npos) << row.fix;
  EXPECT_NE(row.fix.find("noise to the controls"), std::string::npos) << row.fix;
  EXPECT_EQ(row.fix.find("--"), std::string::npos) << row.fix;  // the library's words, no flag

  CheckRow failed;
  failed.status = CheckStatus::kFail;
  JudgeIdenticalWorlds(o, &failed);
  EXPECT_EQ(failed.status, CheckStatus::kFail);  // one world's difference is a finding

  CrosscheckOptions noisy = o;
  noisy.ctrl_noise = 0.01;
  CrosscheckOptions randomized = o;
  randomized.randomize.push_back(ParseRandomization(model, "dof_damping[hinge]=U(0,0.5)"));
  for (const CrosscheckOptions& varied : {noisy, randomized}) {
    EXPECT_FALSE(WorldsAreIdentical(varied));
    CheckRow pass;
    pass.status = CheckStatus::kPass;
    JudgeIdenticalWorlds(varied, &pass);
    EXPECT_EQ(pass.status, CheckStatus::kPass);
  }
}

}  // namespace
}  // namespace plumb
