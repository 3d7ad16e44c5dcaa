// The recommendation rule plumb converge and plumb verify share (RecommendedLevel), and the
// solref time constants held across the ladder (HoldSolref).

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "fixture.h"
#include "plumb/converge.h"
#include "plumb/metric.h"

namespace plumb {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// Levels at 0.002 / 2^k with the given error estimates and spreads.
std::vector<ConvergenceLevel> Levels(const std::vector<double>& errors,
                                     const std::vector<double>& spreads) {
  std::vector<ConvergenceLevel> levels;
  for (std::size_t k = 0; k < errors.size(); ++k) {
    ConvergenceLevel l;
    l.dt = 0.002 / std::pow(2.0, k);
    l.error = errors[k];
    l.spread = spreads[k];
    levels.push_back(l);
  }
  return levels;
}

TEST(RecommendedLevelTest, FallingErrorsRecommendTheCoarsestThatMeetsTheTolerance) {
  auto levels = Levels({8e-3, 4e-3, 2e-3, 1e-3, 5e-4}, {8e-3, 4e-3, 2e-3, 1e-3, 1e-3});
  EXPECT_EQ(RecommendedLevel(levels, 5e-3), 1);
  EXPECT_EQ(RecommendedLevel(levels, 1e-2), 0);
  EXPECT_EQ(RecommendedLevel(levels, 1e-4), -1);  // none: not a step below the finest
}

// Regression (issue 45): the coarsest level whose own estimate met the tolerance was
// recommended though a finer level failed, so verify said "not converged at dt = 0.002 s ...
// the largest timestep that would pass is 0.004 s".
TEST(RecommendedLevelTest, NeverNamesALevelCoarserThanOneThatFails) {
  // estimates that do not fall with dt: small at the coarsest, large at the next
  auto levels = Levels({1e-4, 3e-2, 2e-3, 1e-3, 5e-4}, {3e-3, 3e-3, 2e-3, 1e-3, 1e-3});
  EXPECT_EQ(RecommendedLevel(levels, 5e-3), 2);
  // a spread beyond the tolerance fails a level whatever its own estimate says
  levels = Levels({1e-4, 1e-4, 1e-4, 1e-4, 1e-4}, {1e-4, 9e-3, 1e-4, 1e-4, 1e-4});
  EXPECT_EQ(RecommendedLevel(levels, 5e-3), 2);
}

TEST(RecommendedLevelTest, WithoutAnOrderTheDifferencesDecide) {
  // no order (every error NaN): levels far inside the tolerance pass, as on the Panda
  auto levels = Levels({kNaN, kNaN, kNaN, kNaN, kNaN}, {3e-4, 1.5e-4, 5e-5, 3e-5, 3e-5});
  EXPECT_EQ(RecommendedLevel(levels, 0.034), 0);
  EXPECT_EQ(RecommendedLevel(levels, 1e-4), 2);
  // the finest level without an estimate is judged by its difference to the next coarser
  levels = Levels({kNaN, kNaN, kNaN, kNaN, kNaN}, {1, 1, 1, 1, 1});
  EXPECT_EQ(RecommendedLevel(levels, 0.034), -1);
  // nothing finer than the finest: its Richardson estimate is all there is
  levels = Levels({kNaN, kNaN, kNaN, kNaN, 1e-3}, {1, 1, 1, 1, 1});
  EXPECT_EQ(RecommendedLevel(levels, 0.034), 4);
}

// A ball dropped on a plane, both with a contact solref time constant of 1 ms (their
// default class), below 2 * dt at every level but the finest: MuJoCo raises it to 2 * dt, so
// without the hold each level ran a different contact stiffness, and the ball rested 4x
// deeper at dt than at dt/2.
constexpr char kStiffContact[] = R"(<mujoco><option timestep="0.002"/>
  <default><geom solref="0.001 1"/></default>
  <worldbody>
    <geom name="floor" type="plane" size="1 1 0.1"/>
    <body name="ball" pos="0 0 0.12"><freejoint/><geom type="sphere" size="0.1" mass="1"/></body>
  </worldbody></mujoco>)";

class HoldSolrefTest : public testing::MujocoTest {
 protected:
  Model model_ = Model::FromXmlString(kStiffContact);
};

TEST_F(HoldSolrefTest, RaisesOnlyTheTimeConstantsBelowTheFloor) {
  std::string held;
  std::vector<Assignment> sets = HoldSolref(model_, 0.004, &held);
  ASSERT_EQ(sets.size(), 1u);
  EXPECT_EQ(sets[0].path.field, "geom_solref");
  EXPECT_EQ(held, "geom_solref (2)");
  ASSERT_EQ(sets[0].values.size(), 4u);  // two geoms x mjNREF
  EXPECT_EQ(sets[0].values, std::vector<double>({0.004, 1, 0.004, 1}));  // damping ratios kept
  EXPECT_TRUE(HoldSolref(model_, 0.001).empty());  // nothing below 1 ms
  // with refsafe off MuJoCo clamps nothing, so there is nothing to hold
  Model unsafe = model_.Clone();
  unsafe.get_mutable()->opt.disableflags |= mjDSBL_REFSAFE;
  EXPECT_TRUE(HoldSolref(unsafe, 0.004).empty());
  // a stiff floor under a default ball: their contact mixes to 0.0105 s, which MuJoCo never
  // clamps, so nothing is raised (raising the floor's alone would soften that contact)
  Model mixed = model_.Clone();
  mixed.get_mutable()->geom_solref[mjNREF * 1] = 0.02;
  EXPECT_TRUE(HoldSolref(mixed, 0.004).empty());
}

// Only constraints that can exist are held (and reported): the chapter's pendulum at 20 ms has
// default solrefs (20 ms, below the 40 ms floor) on an unlimited hinge without friction loss,
// which make no constraint; a limit or friction loss does.
TEST_F(HoldSolrefTest, HoldsOnlyConstraintsThatExist) {
  Model pendulum = Model::Load(testing::kPendulum);
  EXPECT_TRUE(HoldSolref(pendulum, 0.04).empty());
  Model limited = pendulum.Clone();
  limited.get_mutable()->jnt_limited[0] = 1;
  limited.get_mutable()->dof_frictionloss[0] = 0.1;
  std::string held;
  EXPECT_EQ(HoldSolref(limited, 0.04, &held).size(), 2u);
  EXPECT_EQ(held, "jnt_solref (1), dof_solref (1)");
}

TEST_F(HoldSolrefTest, TheLevelsRunOneModel) {
  Metric z = ParseMetric(model_, "qpos[2]@1");  // the ball's height, at rest by 1 s
  // what the ladder measured before: the model's solref, clamped differently at each level
  std::vector<double> unheld;
  for (double dt : {0.002, 0.001, 0.0005}) unheld.push_back(Measure(model_, {}, z, dt, 1).value);
  double model_change = std::fabs(unheld[0] - unheld[1]);
  ConvergenceResult r = Converge(model_, {}, z, 0.002, 2, 1e-3, 1);
  ASSERT_TRUE(r.ok) << r.problem;
  EXPECT_EQ(r.solref_floor, 0.004);
  EXPECT_NE(SolrefNote(r).find("held at 0.004 s across levels"), std::string::npos)
      << SolrefNote(r);
  // the coarsest level is the model as it runs at its own timestep
  EXPECT_NEAR(r.levels[0].value, unheld[0], 1e-12);
  // the rest depth no longer changes with dt: the levels agree far better than before
  EXPECT_GT(model_change, 1e-5) << unheld[0] << " " << unheld[1];
  EXPECT_LT(r.levels[0].diff, model_change / 100) << r.levels[0].value << " " << r.levels[1].value;
  EXPECT_EQ(r.recommended_dt, 0.002);
}

}  // namespace
}  // namespace plumb
