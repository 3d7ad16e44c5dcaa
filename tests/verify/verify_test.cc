#include "plumb/verify.h"

#include <gtest/gtest.h>

#include <cmath>

#include "fixture.h"
#include "plumb/check_table.h"
#include "plumb/error.h"
#include "verify/verify_rows.h"

namespace plumb {
namespace {

using testing::Find;

std::string Failures(const VerifyReport& report) {
  std::string out;
  for (const CheckRow& c : report.checks) {
    if (c.status == CheckStatus::kFail) out += c.id + ": " + c.explanation + "\n";
  }
  return out;
}

class VerifyTest : public testing::MujocoTest {
 protected:
  VerifyReport VerifyPendulum(const std::vector<std::string>& sets) {
    VerifyOptions options;
    for (const std::string& s : sets) options.sets.push_back(ParseAssignment(pendulum_, s));
    return Verify(pendulum_, options);
  }
  Model pendulum_ = Model::Load(testing::kPendulum);
};

TEST_F(VerifyTest, ChaptersPendulumPassesEveryCheck) {
  VerifyReport report = VerifyPendulum({"qpos[hinge]=0.7"});
  EXPECT_FALSE(report.failed()) << Failures(report);
  EXPECT_EQ(report.Count(CheckStatus::kSkip), 0);
  for (const char* id :
       {"load", "determinism", "warnings", "convergence", "energy", "analytic.period",
        "analytic.damping", "experiment.A", "experiment.B", "experiment.C", "exercise.moon_gravity",
        "exercise.density", "exercise.radians"}) {
    EXPECT_EQ(Find(report, id).status, CheckStatus::kPass)
        << id << ": " << Find(report, id).explanation;
  }
  // RK4 at dt = 1e-4 against the elliptic integral: far inside 1e-6
  EXPECT_LT(Find(report, "analytic.period").rel_error, 1e-9);
  EXPECT_LT(Find(report, "experiment.A").rel_error, 1e-6);
}

TEST_F(VerifyTest, MoonGravityStretchesThePeriodBy2_461) {
  VerifyReport report = VerifyPendulum({"qpos[hinge]=0.7"});
  const CheckRow& moon = Find(report, "exercise.moon_gravity");
  EXPECT_NEAR(moon.measured.value, std::sqrt(9.81 / 1.62), 1e-6);
  EXPECT_NEAR(moon.measured.value, 2.461, 1e-3);
}

TEST_F(VerifyTest, DensityCompilesToDensityTimesCapsuleVolume) {
  VerifyReport report = VerifyPendulum({"qpos[hinge]=0.7"});
  const CheckRow& density = Find(report, "exercise.density");
  // capsule radius 0.05, cylinder length 1: V = pi r^2 L + 4/3 pi r^3
  double volume = M_PI * 0.05 * 0.05 * 1.0 + 4.0 / 3 * M_PI * std::pow(0.05, 3);
  EXPECT_NEAR(density.measured.value, 1000 * volume, 1e-9);
  EXPECT_EQ(density.status, CheckStatus::kPass);
}

TEST_F(VerifyTest, LargeTimestepIsFlaggedAsNotConverged) {
  VerifyReport report = VerifyPendulum({"qpos[hinge]=0.7", "opt.timestep=0.02"});
  const CheckRow& convergence = Find(report, "convergence");
  EXPECT_EQ(convergence.status, CheckStatus::kFail) << convergence.explanation;
  EXPECT_NE(convergence.explanation.find("largest timestep that would pass"), std::string::npos);
  EXPECT_TRUE(report.failed());
}

TEST_F(VerifyTest, AngleThatLooksLikeDegreesIsFlagged) {
  VerifyReport report = VerifyPendulum({"qpos[hinge]=30"});
  const CheckRow& radians = Find(report, "exercise.radians");
  EXPECT_EQ(radians.status, CheckStatus::kWarn);
  EXPECT_NE(radians.explanation.find("4.77 turns"), std::string::npos) << radians.explanation;
  EXPECT_FALSE(report.failed()) << Failures(report);
}

TEST_F(VerifyTest, NegativeDampingThatAddsEnergyFails) {
  VerifyReport report = VerifyPendulum({"qpos[hinge]=0.7", "dof_damping[hinge]=-0.05"});
  EXPECT_EQ(Find(report, "energy").status, CheckStatus::kFail)
      << Find(report, "energy").explanation;
}

TEST_F(VerifyTest, UndampedRk4ConservesEnergy) {
  VerifyReport report =
      VerifyPendulum({"qpos[hinge]=0.7", "dof_damping[hinge]=0", "opt.integrator=RK4"});
  const CheckRow& energy = Find(report, "energy");
  EXPECT_EQ(energy.status, CheckStatus::kPass) << energy.explanation;
  EXPECT_LT(energy.measured.value, 1e-6);
}

TEST_F(VerifyTest, AtRestPendulumSkipsWhatNeedsASwing) {
  VerifyReport report = VerifyPendulum({});
  EXPECT_FALSE(report.failed()) << Failures(report);
  EXPECT_EQ(Find(report, "analytic.period").status, CheckStatus::kSkip);
}

// Every check appears once, in the protocol's order, for a pendulum and for any other model
// (whose pendulum rows are SKIPs that say why).
TEST_F(VerifyTest, EveryCheckIsOneRowInProtocolOrder) {
  const std::vector<std::string> order = {"load",
                                          "start",
                                          "determinism",
                                          "warnings",
                                          "convergence",
                                          "energy",
                                          "analytic.period",
                                          "analytic.model_settings",
                                          "analytic.damping",
                                          "experiment.A",
                                          "experiment.B",
                                          "experiment.C",
                                          "exercise.moon_gravity",
                                          "exercise.density",
                                          "exercise.radians"};
  for (const VerifyReport& report :
       {VerifyPendulum({"qpos[hinge]=0.7"}), Verify(Model::Load(testing::kHumanoid), {})}) {
    std::vector<std::string> ids;
    for (const CheckRow& c : report.checks) {
      ids.push_back(c.id);
      EXPECT_FALSE(c.title.empty()) << c.id;
    }
    EXPECT_EQ(ids, order);
  }
  VerifyReport humanoid = Verify(Model::Load(testing::kHumanoid), {});
  EXPECT_NE(Find(humanoid, "experiment.B").explanation.find("not a single hinge pendulum"),
            std::string::npos)
      << Find(humanoid, "experiment.B").explanation;
}

TEST_F(VerifyTest, HumanoidHasNoFailure) {
  VerifyReport report = Verify(Model::Load(testing::kHumanoid), {});
  EXPECT_FALSE(report.failed()) << Failures(report);
  EXPECT_EQ(Find(report, "analytic.period").status, CheckStatus::kSkip);
  EXPECT_EQ(Find(report, "load").status, CheckStatus::kPass);
}

// A large model's nominal run is cut to a step budget from its size (a flex model passed
// `warnings` on 0.096 s where `run` diverged at 0.533 s, and nothing said so): every row
// judged on it and the summary say how long it simulated and how to judge longer.
TEST_F(VerifyTest, AShortenedHorizonIsSaidInEveryRowItJudgesAndTheSummary) {
  Model humanoid = Model::Load(testing::kHumanoid);  // nv = 27, timestep 0.005
  VerifyReport report = Verify(humanoid, {});
  EXPECT_DOUBLE_EQ(report.horizon.until, 1.25);
  EXPECT_EQ(report.horizon.steps, 250);
  EXPECT_DOUBLE_EQ(report.horizon.requested, 2);
  ASSERT_TRUE(report.horizon.shortened());
  EXPECT_EQ(report.horizon.why, "verify's step budget for a model with nv = 27 is 250 steps");
  for (const char* id : {"determinism", "warnings", "convergence"}) {
    EXPECT_NE(Find(report, id).explanation.find("Judged on 1.25 s simulated (250 steps), not 2 s"),
              std::string::npos)
        << id << ": " << Find(report, id).explanation;
  }
  EXPECT_EQ(Find(report, "load").explanation.find("Judged on"), std::string::npos);
  std::string table = VerifyTable(report, TableDetail::kFindings, "");
  EXPECT_NE(table.find("Judged on 1.25 s of simulated time (250 steps), not 2 s"),
            std::string::npos)
      << table;
  // the same budget whatever the machine's speed; asking for 2 s gets 2 s
  VerifyOptions longer;
  longer.until = 2;
  VerifyReport full = Verify(humanoid, longer);
  EXPECT_DOUBLE_EQ(full.horizon.until, 2);
  EXPECT_FALSE(full.horizon.shortened());
  EXPECT_EQ(Find(full, "warnings").explanation.find("Judged on"), std::string::npos);
  // the chapter's pendulum runs its 2 s
  EXPECT_FALSE(VerifyPendulum({"qpos[hinge]=0.7"}).horizon.shortened());
}

// issue 46: the budget is whole steps ("of 204.082 steps" for nv = 490), and an until beyond 2^53
// steps is refused by the one rule, without suggesting itself ("Use 1e+30")
TEST_F(VerifyTest, TheStepBudgetIsWholeStepsAndAHugeUntilIsRefused) {
  std::string bodies;
  for (int i = 0; i < 70; ++i) {  // nv = 420: 1e5 / 420 = 238.1
    bodies += "<body pos='" + std::to_string(i) + " 0 1'><freejoint/><geom size='0.1'/></body>";
  }
  Model model = Model::FromXmlString("<mujoco><worldbody>" + bodies + "</worldbody></mujoco>");
  VerifyHorizon h = NominalHorizon(model, {});
  EXPECT_EQ(h.steps, 238);
  EXPECT_EQ(h.why, "verify's step budget for a model with nv = 420 is 238 steps");
  VerifyOptions huge;
  huge.until = 1e30;
  try {
    NominalHorizon(model, huge);
    FAIL() << "until 1e30 was accepted";
  } catch (const ArgumentError& e) {
    EXPECT_EQ(e.argument(), "until");
    EXPECT_NE(e.problem().find("2^53"), std::string::npos) << e.problem();
    EXPECT_EQ(e.problem().find("Use "), std::string::npos) << e.problem();
  }
}

TEST_F(VerifyTest, FreeBoxOnAPlaneGetsWhatApplies) {
  Model box = Model::FromXmlString(R"(<mujoco><worldbody>
      <geom type="plane" size="2 2 0.1"/>
      <body pos="0 0 0.5"><freejoint/><geom type="box" size="0.1 0.1 0.1" mass="1"/></body>
    </worldbody></mujoco>)",
                                   "box.xml");
  VerifyReport report = Verify(box, {});
  EXPECT_FALSE(report.failed()) << Failures(report);
  EXPECT_EQ(Find(report, "determinism").status, CheckStatus::kPass);
  // judged on the free fall, before the box lands (contacts bound energy only roughly)
  const CheckRow& energy = Find(report, "energy");
  EXPECT_EQ(energy.status, CheckStatus::kPass) << energy.explanation;
  EXPECT_NE(energy.explanation.find("Judged on the first"), std::string::npos);
  EXPECT_NE(energy.explanation.find("contacts occur"), std::string::npos) << energy.explanation;
}

// Regression: converge printed orders like -3.12 on contact-rich models with no word,
// while verify said it only in some branches; both now give ContactCaveat's text.
TEST_F(VerifyTest, ConvergenceGivesTheContactCaveat) {
  Model box = Model::FromXmlString(R"(<mujoco><worldbody>
      <geom type="plane" size="2 2 0.1"/>
      <body pos="0 0 0.2"><freejoint/><geom type="box" size="0.1 0.1 0.1" mass="1"/></body>
    </worldbody></mujoco>)",
                                   "box.xml");
  VerifyReport report = Verify(box, {});
  const CheckRow& convergence = Find(report, "convergence");
  EXPECT_NE(convergence.explanation.find("Caveat: contacts occur (up to"), std::string::npos)
      << convergence.explanation;
  EXPECT_EQ(Find(VerifyPendulum({"qpos[hinge]=0.7"}), "convergence").explanation.find("Caveat"),
            std::string::npos);
}

// Regression: --until 0 ran zero steps and PASSed determinism and warnings.
TEST_F(VerifyTest, ARunOfZeroStepsIsRefused) {
  VerifyOptions options;
  options.until = 0;
  EXPECT_THROW(Verify(pendulum_, options), ValueError);
  options.until = 0.003;  // not a whole number of dt = 0.002 s
  EXPECT_THROW(Verify(pendulum_, options), ValueError);
  // an odd number of steps is a whole number of the ladder's coarsest level, the model's dt
  options.until = 0.006;
  EXPECT_EQ(Verify(pendulum_, options).horizon.steps, 3);
}

TEST_F(VerifyTest, AnEngagedLimitIsNotAConservativeSystem) {
  // undamped RK4 would conserve energy, but the limit's soft spring stores some of it
  Model model = Model::FromXmlString(R"(<mujoco><compiler angle="radian"/>
      <option integrator="RK4"/><worldbody><body pos="0 0 1.5">
        <joint name="hinge" axis="0 1 0" limited="true" range="-0.3 0.3"/>
        <geom type="capsule" fromto="0 0 0 0 0 -1" size="0.05" mass="1"/></body></worldbody></mujoco>)");
  VerifyOptions options;
  options.sets = {ParseAssignment(model, "qpos[hinge]=0.25"),
                  ParseAssignment(model, "qvel[hinge]=2")};
  VerifyReport report = Verify(model, options);
  EXPECT_EQ(Find(report, "energy").status, CheckStatus::kSkip)
      << Find(report, "energy").explanation;
  EXPECT_NE(Find(report, "energy").explanation.find("limit"), std::string::npos);
  EXPECT_EQ(Find(report, "analytic.period").status, CheckStatus::kSkip);
  EXPECT_FALSE(report.failed()) << Failures(report);
}

TEST_F(VerifyTest, APluginActuatorIsNotAPassiveSystem) {
  if (mjVERSION_HEADER < 300) GTEST_SKIP() << "MuJoCo 2.x has no plugins";
  // as MuJoCo's own mujoco.pid sample: sliders under gravity, each held by a pid plugin (a
  // P-only one bounces, adding energy the plugin's way); at ctrl = 0 nothing plain pushes,
  // yet the plugin does
  Model model = Model::FromXmlString(R"(<mujoco>
      <extension><plugin plugin="mujoco.pid">
        <instance name="p_only"><config key="kp" value="4"/></instance>
        <instance name="pd"><config key="kp" value="4"/><config key="kd" value="0.4"/></instance>
      </plugin></extension>
      <worldbody><geom type="plane" pos="0 0 -0.1" size="0 0 10"/>
        <body pos="-0.05 0 0"><joint name="a" type="slide" axis="0 0 1"/><geom size="0.01"/></body>
        <body pos="0.05 0 0"><joint name="b" type="slide" axis="0 0 1"/><geom size="0.01"/></body>
      </worldbody>
      <actuator><plugin name="bouncy" joint="a" plugin="mujoco.pid" instance="p_only" ctrlrange="0 0.15"/>
        <plugin joint="b" plugin="mujoco.pid" instance="pd" ctrlrange="0 0.15"/></actuator>
    </mujoco>)");
  VerifyReport report = Verify(model, {});
  const CheckRow& energy = Find(report, "energy");
  EXPECT_EQ(energy.status, CheckStatus::kSkip) << energy.explanation;
  EXPECT_NE(energy.explanation.find("actuator 'bouncy' comes from a plugin (mujoco.pid)"),
            std::string::npos)
      << energy.explanation;
  EXPECT_FALSE(report.failed()) << Failures(report);
}

// MuJoCo's fatal error in a run (an arena too small for the contacts) ends that run, not the
// protocol: verify still reports every check, and the failed run's row says what to raise
TEST_F(VerifyTest, AFatalErrorInARunIsARowNotTheEnd) {
  if (!(mjVERSION_HEADER >= 4000000)) GTEST_SKIP() << "the arena size is 4.0.1's";
  Model model = Model::FromXmlString(R"(<mujoco><size memory="24K"/><worldbody>
      <geom type="plane" size="2 2 .1"/>
      <body pos="0 0 0.3"><freejoint/><geom type="box" size=".1 .1 .02" mass="1"/>
        <geom type="box" size=".02 .1 .1" pos="0.1 0 0" mass="1"/></body>
      <body pos="0.3 0 0.3"><freejoint/><geom type="box" size=".1 .1 .1" mass="1"/></body>
      <body pos="-0.3 0 0.3"><freejoint/><geom type="box" size=".1 .1 .1" mass="1"/></body>
    </worldbody></mujoco>)");
  VerifyReport report = Verify(model, {});
  EXPECT_EQ(report.checks.size(), 15u);
  const CheckRow& warnings = Find(report, "warnings");
  EXPECT_EQ(warnings.status, CheckStatus::kFail);
  EXPECT_EQ(warnings.measured_text, "stopped by MuJoCo");
  EXPECT_NE(warnings.explanation.find("mj_stackAlloc"), std::string::npos) << warnings.explanation;
  EXPECT_NE(warnings.explanation.find("<size memory=\"2M\"/>"), std::string::npos)
      << warnings.explanation;
  EXPECT_EQ(Find(report, "convergence").status, CheckStatus::kSkip);
  EXPECT_EQ(Find(report, "load").status, CheckStatus::kPass);
}

TEST_F(VerifyTest, CoupledJointsAreNotHeldToFallingPeaks) {
  // a damped double pendulum: energy only falls, but one link may swing higher as the
  // other hands it energy; only the total-energy test applies
  Model model = Model::FromXmlString(R"(<mujoco><option integrator="RK4"/><worldbody>
      <body pos="0 0 2"><joint name="shoulder" axis="0 1 0" damping="0.01"/>
        <geom type="capsule" fromto="0 0 0 0 0 -0.5" size="0.03" mass="1"/>
        <body pos="0 0 -0.5"><joint name="elbow" axis="0 1 0" damping="0.01"/>
          <geom type="capsule" fromto="0 0 0 0 0 -0.5" size="0.03" mass="0.5" contype="0"
                conaffinity="0"/></body></body></worldbody></mujoco>)");
  VerifyOptions options;
  options.sets = {ParseAssignment(model, "qpos[shoulder]=0.9")};
  options.until = 4;
  VerifyReport report = Verify(model, options);
  const CheckRow& energy = Find(report, "energy");
  EXPECT_EQ(energy.status, CheckStatus::kPass) << energy.explanation;
  EXPECT_NE(energy.explanation.find("coupled"), std::string::npos) << energy.explanation;
}

TEST_F(VerifyTest, ConvergenceIsJudgedOnTheSwingNotTheOffset) {
  // the same swing about q = 0 and about q = 100 (a hinge whose zero is 100 rad away)
  // must get the same verdict: errors are compared with the amplitude, not |q|
  VerifyOptions near, far;
  near.sets = {ParseAssignment(pendulum_, "qpos[hinge]=0.7"),
               ParseAssignment(pendulum_, "opt.timestep=0.02")};
  far.sets = {ParseAssignment(pendulum_, "qpos[hinge]=" + std::to_string(0.7 + 32 * M_PI)),
              ParseAssignment(pendulum_, "opt.timestep=0.02")};
  const CheckRow a = Find(Verify(pendulum_, near), "convergence");
  const CheckRow b = Find(Verify(pendulum_, far), "convergence");
  EXPECT_EQ(a.status, b.status) << a.explanation << "\n" << b.explanation;
  EXPECT_NE(a.status, CheckStatus::kPass) << a.explanation;
  EXPECT_NEAR(a.reference.value, b.reference.value, 1e-6 * a.reference.value);
}

// Found by tests/hostile/hostile_models.py: the load check passed a model with a NaN.
TEST_F(VerifyTest, ANaNParameterFailsTheLoadCheck) {
  Model model = Model::FromXmlString(testing::kNonFiniteXml, "nan.xml");
  TakeMujocoWarnings();
  VerifyReport report = Verify(model, {});
  const CheckRow& load = Find(report, "load");
  EXPECT_EQ(load.status, CheckStatus::kFail);
  EXPECT_NE(load.explanation.find("dof_damping[hinge] = nan"), std::string::npos)
      << load.explanation;
}

TEST_F(VerifyTest, StopsWhenItsCallerAsks) {
  VerifyOptions options;
  options.sets = {ParseAssignment(pendulum_, "qpos[hinge]=0.7")};
  StopSource stop;
  stop.RequestStop();
  options.stop = stop.token();
  EXPECT_THROW(Verify(pendulum_, options), Interrupted);
}

}  // namespace
}  // namespace plumb
