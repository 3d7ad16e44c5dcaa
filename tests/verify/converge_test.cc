#include "plumb/converge.h"

#include <gtest/gtest.h>

#include <cmath>

#include "fixture.h"
#include "plumb/analytic.h"
#include "plumb/error.h"

namespace plumb {
namespace {

TEST(EstimateOrderTest, RecoversAManufacturedOrder) {
  // v(dt) = 1 + 3*dt^2 at dt = 0.1 / 2^k
  std::vector<double> values, diffs;
  for (int k = 0; k < 5; ++k) values.push_back(1 + 3 * std::pow(0.1 / std::pow(2, k), 2));
  for (int k = 0; k < 4; ++k) diffs.push_back(std::fabs(values[k] - values[k + 1]));
  OrderEstimate e = EstimateOrder(values, diffs, 1e-15);
  ASSERT_TRUE(e.resolved);
  EXPECT_NEAR(e.order, 2, 1e-9);
  EXPECT_NEAR(e.extrapolated, 1, 1e-12);
  EXPECT_EQ(e.noise_from, -1);
}

TEST(EstimateOrderTest, DoesNotExtrapolateFromRoundOff) {
  std::vector<double> values = {1.0 + 1e-8, 1.0 + 1e-9, 1.0 + 2e-16, 1.0 - 1e-16, 1.0};
  std::vector<double> diffs = {9e-9, 1e-9, 3e-16, 1e-16};
  OrderEstimate e = EstimateOrder(values, diffs, 1e-14);
  EXPECT_TRUE(e.resolved);  // from the clean coarse pair
  EXPECT_EQ(e.noise_from, 2);
  EXPECT_EQ(e.extrapolated, values.back());  // the finest value, not an extrapolation
  OrderEstimate noise = EstimateOrder(values, {1e-16, 2e-16, 1e-16, 3e-16}, 1e-14);
  EXPECT_FALSE(noise.resolved);
  EXPECT_EQ(noise.extrapolated, values.back());
  EXPECT_NE(noise.note.find("round-off"), std::string::npos);
}

class ConvergeTest : public testing::MujocoTest {
 protected:
  Model pendulum_ = Model::Load(testing::kPendulum);
  std::vector<Assignment> Start(const std::string& integrator = "Euler") {
    return {ParseAssignment(pendulum_, "qpos[hinge]=0.7"),
            ParseAssignment(pendulum_, "opt.integrator=" + integrator)};
  }
};

TEST_F(ConvergeTest, EulerIsFirstOrder) {
  Metric q2 = ParseMetric(pendulum_, "qpos[hinge]@2");
  ConvergenceResult r = Converge(pendulum_, Start(), q2, 0.002, 4, 1e-3, 2);
  ASSERT_TRUE(r.ok) << r.problem;
  ASSERT_TRUE(r.estimate.resolved);
  EXPECT_NEAR(r.estimate.order, 1.0, 0.05);
  // the model's own dt: q(2) of the chapter's pendulum with Euler, as MuJoCo 2.2.2 computes
  // it (`plumb run models/pendulum.xml --set 'qpos[hinge]=0.7' --until 2 --every 2 --format csv`)
  EXPECT_NEAR(r.levels[0].value, 0.310947692600239, 1e-12);
  EXPECT_GT(r.recommended_dt, 0);
  EXPECT_LT(r.recommended_dt, 0.002);  // 1e-3 of the scale needs a smaller step
}

TEST_F(ConvergeTest, Rk4IsFourthOrder) {
  Metric q2 = ParseMetric(pendulum_, "qpos[hinge]@2");
  // two coarsest steps, so the order is not an accident of one ladder
  for (double dt0 : {0.02, 0.01}) {
    ConvergenceResult r = Converge(pendulum_, Start("RK4"), q2, dt0, 4, 1e-3, 2);
    ASSERT_TRUE(r.estimate.resolved) << dt0 << ": " << r.estimate.note;
    EXPECT_NEAR(r.estimate.order, 4.0, 0.3) << dt0;
  }
  // at the model's own step RK4 reaches round-off: reported, not extrapolated from noise
  ConvergenceResult fine = Converge(pendulum_, Start("RK4"), q2, 0.002, 4, 1e-3, 2);
  EXPECT_GE(fine.estimate.noise_from, 0);
  EXPECT_EQ(fine.estimate.extrapolated, fine.levels.back().value);
}

// A double pendulum of our own: two hinged capsules, no damping, a chaotic-capable
// system that is still smooth over one second.
constexpr char kDoublePendulum[] = R"(
<mujoco model="double">
  <option timestep="0.002"/>
  <worldbody>
    <body name="upper" pos="0 0 2">
      <joint name="shoulder" axis="0 1 0"/>
      <geom type="capsule" fromto="0 0 0 0 0 -0.5" size="0.03" mass="1" contype="0" conaffinity="0"/>
      <body name="lower" pos="0 0 -0.5">
        <joint name="elbow" axis="0 1 0"/>
        <geom type="capsule" fromto="0 0 0 0 0 -0.5" size="0.03" mass="0.5" contype="0" conaffinity="0"/>
      </body>
    </body>
  </worldbody>
</mujoco>)";

TEST_F(ConvergeTest, DoublePendulumOrdersMatchTheIntegrators) {
  Model model = Model::FromXmlString(kDoublePendulum, "double.xml");
  std::vector<Assignment> start = {ParseAssignment(model, "qpos[shoulder]=1.0"),
                                   ParseAssignment(model, "qpos[elbow]=-0.5")};
  Metric state = ParseMetric(model, "state@1");
  ConvergenceResult euler = Converge(model, start, state, 0.002, 4, 1e-3, 1);
  ASSERT_TRUE(euler.estimate.resolved);
  EXPECT_NEAR(euler.estimate.order, 1.0, 0.1);
  start.push_back(ParseAssignment(model, "opt.integrator=RK4"));
  ConvergenceResult rk4 = Converge(model, start, state, 0.02, 4, 1e-3, 1);
  ASSERT_TRUE(rk4.estimate.resolved);
  EXPECT_NEAR(rk4.estimate.order, 4.0, 0.3);
}

TEST_F(ConvergeTest, EnergyDriftShrinksWithTheTimestep) {
  std::vector<Assignment> undamped = Start();
  undamped.push_back(ParseAssignment(pendulum_, "dof_damping[hinge]=0"));
  Metric drift = ParseMetric(pendulum_, "energy_drift");
  double previous = INFINITY;
  for (double dt : {0.004, 0.002, 0.001, 0.0005}) {
    Measurement m = Measure(pendulum_, undamped, drift, dt, 2);
    ASSERT_TRUE(m.ok);
    EXPECT_LT(std::fabs(m.value), previous) << "dt = " << dt;
    previous = std::fabs(m.value);
  }
  EXPECT_LT(previous, 1e-3);
}

TEST_F(ConvergeTest, DampingRemovesEnergy) {
  Metric drift = ParseMetric(pendulum_, "energy_drift");
  Measurement damped = Measure(pendulum_, Start("RK4"), drift, 0.001, 2);
  ASSERT_TRUE(damped.ok);
  EXPECT_LT(damped.value, -0.01);  // damping 0.05 takes energy out
}

TEST_F(ConvergeTest, PeriodMetricMatchesTheEllipticPeriod) {
  for (double theta : {0.1, 0.7, 2.8}) {
    std::vector<Assignment> sets = {
        ParseAssignment(pendulum_, "qpos[hinge]=" + std::to_string(theta)),
        ParseAssignment(pendulum_, "dof_damping[hinge]=0"),
        ParseAssignment(pendulum_, "opt.integrator=RK4")};
    Measurement m =
        Measure(pendulum_, sets, ParseMetric(pendulum_, "period(qpos[hinge])"), 1e-4, 8);
    ASSERT_TRUE(m.ok) << m.problem;
    PendulumParams p = *DetectPendulum(pendulum_);
    EXPECT_NEAR(m.value / LargeAnglePeriod(p, theta), 1, 1e-6) << theta;
  }
}

TEST_F(ConvergeTest, MetricsParseAndRejectNonsense) {
  EXPECT_EQ(ParseMetric(pendulum_, "qpos[hinge]@2").kind, MetricKind::kValueAt);
  EXPECT_EQ(ParseMetric(pendulum_, "period( qpos[hinge] )").kind, MetricKind::kPeriod);
  EXPECT_EQ(ParseMetric(pendulum_, "maxabs(qvel[hinge])").kind, MetricKind::kMaxAbs);
  EXPECT_EQ(ParseMetric(pendulum_, "state@1").time, 1);
  EXPECT_THROW(ParseMetric(pendulum_, "qpos[hinge]@soon"), ValueError);
  EXPECT_THROW(ParseMetric(pendulum_, "mean(qpos[hinge])"), ValueError);
  EXPECT_THROW(ParseMetric(pendulum_, "qpos[hnge]@2"), PathError);
  EXPECT_THROW(Measure(pendulum_, {}, ParseMetric(pendulum_, "qpos[hinge]@0.0031"), 0.002, 1),
               ValueError);
  EXPECT_THROW(Converge(pendulum_, {}, ParseMetric(pendulum_, "qpos[hinge]@2"), 0.002, 1, 1e-3, 2),
               ValueError);
}

TEST_F(ConvergeTest, ExpectedOrders) {
  EXPECT_EQ(ExpectedOrder(mjINT_EULER), 1);
  EXPECT_EQ(ExpectedOrder(mjINT_RK4), 4);
  EXPECT_EQ(ExpectedOrder(mjINT_IMPLICIT), 1);
}

TEST_F(ConvergeTest, AnUnmeasurableMetricIsNotADivergence) {
  // a pendulum at rest never crosses: the period cannot be measured at any dt
  Metric period = ParseMetric(pendulum_, "period(qpos[hinge])");
  ConvergenceResult r = Converge(pendulum_, {}, period, 0.002, 2, 1e-3, 2);
  EXPECT_FALSE(r.ok);
  EXPECT_FALSE(r.diverged);
  EXPECT_NE(r.problem.find("fewer than twice"), std::string::npos) << r.problem;
  for (const ConvergenceLevel& l : r.levels) EXPECT_TRUE(std::isnan(l.value)) << l.dt;
}

TEST_F(ConvergeTest, RoundOffLevelsCarryNoOrder) {
  // RK4 at small steps: the finer differences are round-off, their orders are not shown
  std::vector<Assignment> sets = {ParseAssignment(pendulum_, "qpos[hinge]=0.7"),
                                  ParseAssignment(pendulum_, "opt.integrator=RK4")};
  Metric q2 = ParseMetric(pendulum_, "qpos[hinge]@2");
  ConvergenceResult r = Converge(pendulum_, sets, q2, 0.0005, 4, 1e-3, 2);
  ASSERT_TRUE(r.ok) << r.problem;
  int roundoff = 0;
  for (const ConvergenceLevel& l : r.levels) {
    if (l.roundoff) {
      ++roundoff;
      EXPECT_TRUE(std::isnan(l.order)) << l.dt;
    }
  }
  EXPECT_GE(roundoff, 2);
  // the coarsest level already agrees with every finer one far inside the tolerance
  EXPECT_DOUBLE_EQ(r.recommended_dt, 0.0005);
}

// Regression: converge recommended 0.02 s when the coarsest level was 0.01 s, and
// 7.8e-05 s below the finest: a recommendation is always a level that was run.
TEST_F(ConvergeTest, RecommendsOnlyATestedLevel) {
  Metric q2 = ParseMetric(pendulum_, "qpos[hinge]@2");
  for (double tol : {0.5, 1e-3, 1e-6}) {
    ConvergenceResult r = Converge(pendulum_, Start(), q2, 0.002, 4, tol, 2);
    ASSERT_TRUE(r.ok) << r.problem;
    if (r.recommended_dt == 0) continue;  // none meets the tolerance
    bool tested = false;
    for (const ConvergenceLevel& l : r.levels) tested = tested || l.dt == r.recommended_dt;
    EXPECT_TRUE(tested) << "tol " << tol << ": " << r.recommended_dt;
  }
  // a loose tolerance is met by the coarsest level, not by an untested 2 * dt0
  EXPECT_EQ(Converge(pendulum_, Start(), q2, 0.002, 4, 0.5, 2).recommended_dt, 0.002);
  // a tolerance no level meets recommends nothing, not a step below the finest
  EXPECT_EQ(Converge(pendulum_, Start(), q2, 0.002, 4, 1e-6, 2).recommended_dt, 0);
}

// Regression: the finest level showed "est. error 0.000e+00".
TEST_F(ConvergeTest, FinestLevelHasNoFakeZeroError) {
  Metric q2 = ParseMetric(pendulum_, "qpos[hinge]@2");
  ConvergenceResult euler = Converge(pendulum_, Start(), q2, 0.002, 4, 1e-3, 2);
  const ConvergenceLevel& finest = euler.levels.back();
  EXPECT_TRUE(finest.error_is_richardson);
  // Richardson: half the finest difference for a first-order method
  EXPECT_NEAR(finest.error, euler.levels[3].diff / (std::pow(2.0, euler.estimate.order) - 1),
              1e-15);
  EXPECT_GT(finest.error, 0);
  for (std::size_t i = 0; i + 1 < euler.levels.size(); ++i) {
    EXPECT_FALSE(euler.levels[i].error_is_richardson);
  }
  // where the finest levels agree to round-off, their error is not shown at all
  ConvergenceResult rk4 = Converge(pendulum_, Start("RK4"), q2, 0.002, 4, 1e-3, 2);
  EXPECT_TRUE(std::isnan(rk4.levels.back().error));
  EXPECT_FALSE(rk4.levels.back().error_is_richardson);
}

TEST_F(ConvergeTest, ContactsGiveTheCaveat) {
  Model humanoid = Model::Load(testing::kHumanoid);
  Metric z = ParseMetric(humanoid, "xpos[torso][2]@1");
  ConvergenceResult r = Converge(humanoid, {}, z, 0.005, 2, 1e-3, 1);
  EXPECT_GT(r.max_contacts, 0);
  EXPECT_EQ(r.caveat, ContactCaveat(r.max_contacts));
  EXPECT_NE(r.caveat.find("non-smooth"), std::string::npos) << r.caveat;
  Metric q2 = ParseMetric(pendulum_, "qpos[hinge]@2");
  ConvergenceResult pendulum = Converge(pendulum_, Start(), q2, 0.002, 2, 1e-3, 2);
  EXPECT_EQ(pendulum.max_contacts, 0);
  EXPECT_EQ(pendulum.caveat, "");
}

TEST_F(ConvergeTest, StopsWhenItsCallerAsks) {
  Metric q2 = ParseMetric(pendulum_, "qpos[hinge]@2");
  StopSource stop;
  stop.RequestStop();
  EXPECT_THROW(Converge(pendulum_, Start(), q2, 0.002, 4, 1e-3, 2, stop.token()), Interrupted);
}

}  // namespace
}  // namespace plumb
