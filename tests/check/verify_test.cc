#include "plumb/verify.h"

#include <gtest/gtest.h>

#include <cmath>

#include "fixture.h"

namespace plumb {
namespace {

const CheckResult& Find(const VerifyReport& report, const std::string& id) {
  for (const CheckResult& c : report.checks) {
    if (c.id == id) return c;
  }
  static CheckResult missing;
  ADD_FAILURE() << "no check " << id;
  return missing;
}

std::string Failures(const VerifyReport& report) {
  std::string out;
  for (const CheckResult& c : report.checks) {
    if (c.status == CheckStatus::kFail) out += c.id + ": " + c.detail + "\n";
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
    EXPECT_EQ(Find(report, id).status, CheckStatus::kPass) << id << ": " << Find(report, id).detail;
  }
  // RK4 at dt = 1e-4 against the elliptic integral: far inside 1e-6
  EXPECT_LT(Find(report, "analytic.period").rel_error, 1e-9);
  EXPECT_LT(Find(report, "experiment.A").rel_error, 1e-6);
}

TEST_F(VerifyTest, MoonGravityStretchesThePeriodBy2_461) {
  VerifyReport report = VerifyPendulum({"qpos[hinge]=0.7"});
  const CheckResult& moon = Find(report, "exercise.moon_gravity");
  EXPECT_NEAR(moon.measured_value, std::sqrt(9.81 / 1.62), 1e-6);
  EXPECT_NEAR(moon.measured_value, 2.461, 1e-3);
}

TEST_F(VerifyTest, DensityCompilesToDensityTimesCapsuleVolume) {
  VerifyReport report = VerifyPendulum({"qpos[hinge]=0.7"});
  const CheckResult& density = Find(report, "exercise.density");
  // capsule radius 0.05, cylinder length 1: V = pi r^2 L + 4/3 pi r^3
  double volume = M_PI * 0.05 * 0.05 * 1.0 + 4.0 / 3 * M_PI * std::pow(0.05, 3);
  EXPECT_NEAR(density.measured_value, 1000 * volume, 1e-9);
  EXPECT_EQ(density.status, CheckStatus::kPass);
}

TEST_F(VerifyTest, LargeTimestepIsFlaggedAsNotConverged) {
  VerifyReport report = VerifyPendulum({"qpos[hinge]=0.7", "opt.timestep=0.02"});
  const CheckResult& convergence = Find(report, "convergence");
  EXPECT_EQ(convergence.status, CheckStatus::kFail) << convergence.detail;
  EXPECT_NE(convergence.detail.find("largest timestep that would pass"), std::string::npos);
  EXPECT_TRUE(report.failed());
}

TEST_F(VerifyTest, AngleThatLooksLikeDegreesIsFlagged) {
  VerifyReport report = VerifyPendulum({"qpos[hinge]=30"});
  const CheckResult& radians = Find(report, "exercise.radians");
  EXPECT_EQ(radians.status, CheckStatus::kWarn);
  EXPECT_NE(radians.detail.find("4.77 turns"), std::string::npos) << radians.detail;
  EXPECT_FALSE(report.failed()) << Failures(report);
}

TEST_F(VerifyTest, NegativeDampingThatAddsEnergyFails) {
  VerifyReport report = VerifyPendulum({"qpos[hinge]=0.7", "dof_damping[hinge]=-0.05"});
  EXPECT_EQ(Find(report, "energy").status, CheckStatus::kFail) << Find(report, "energy").detail;
}

TEST_F(VerifyTest, UndampedRk4ConservesEnergy) {
  VerifyReport report =
      VerifyPendulum({"qpos[hinge]=0.7", "dof_damping[hinge]=0", "opt.integrator=RK4"});
  const CheckResult& energy = Find(report, "energy");
  EXPECT_EQ(energy.status, CheckStatus::kPass) << energy.detail;
  EXPECT_LT(energy.measured_value, 1e-6);
}

TEST_F(VerifyTest, AtRestPendulumSkipsWhatNeedsASwing) {
  VerifyReport report = VerifyPendulum({});
  EXPECT_FALSE(report.failed()) << Failures(report);
  EXPECT_EQ(Find(report, "analytic.period").status, CheckStatus::kSkip);
}

TEST_F(VerifyTest, HumanoidHasNoFailure) {
  VerifyReport report = Verify(Model::Load(testing::kHumanoid), {});
  EXPECT_FALSE(report.failed()) << Failures(report);
  EXPECT_EQ(Find(report, "analytic.period").status, CheckStatus::kSkip);
  EXPECT_EQ(Find(report, "load").status, CheckStatus::kPass);
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
  EXPECT_EQ(Find(report, "energy").status, CheckStatus::kSkip);  // contacts
  EXPECT_NE(Find(report, "energy").detail.find("contacts"), std::string::npos);
}

}  // namespace
}  // namespace plumb
