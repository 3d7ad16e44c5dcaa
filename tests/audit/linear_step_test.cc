// The step response of a linear element under MuJoCo's integrators against the exact one
// (src/audit/linear_step.h), on cases with known answers: a resolved oscillator is off by next
// to nothing and its error halves with the step (the Euler-type maps are first order), an
// oscillator at 3 steps a period under implicitfast is off by half its step, an overdamped
// servo whose fast mode lasts a thousandth of a step is fine under implicitfast (it diverges
// under explicit Euler), and the timestep and inertia the bisections return meet the bound.

#include "audit/linear_step.h"

#include <gtest/gtest.h>
#include <mujoco/mujoco.h>

#include <cmath>

namespace plumb::audit {
namespace {

constexpr double kPi = 3.14159265358979323846;
// implicit and implicitfast step a linear element alike (the caller says which damping is
// implicit); MuJoCo 2.2.2 has no mjINT_IMPLICITFAST
constexpr int kImplicitFast = mjINT_IMPLICIT;

// A unit inertia with the given period (s) and damping ratio, its damping all implicit.
LinearElement Oscillator(double period, double zeta) {
  double omega = 2 * kPi / period;
  return {1, omega * omega, 2 * zeta * omega, 2 * zeta * omega};
}

TEST(LinearStepTest, AResolvedOscillatorIsOffByNextToNothing) {
  LinearElement e = Oscillator(1, 0.7);
  EXPECT_LT(StepError(e, 1e-3, kImplicitFast), 1e-3);
  EXPECT_LT(StepError(e, 1e-3, mjINT_RK4), 1e-9);
  EXPECT_FALSE(Diverges(e, 1e-3, mjINT_EULER));
}

TEST(LinearStepTest, TheEulerTypeMapsAreFirstOrder) {
  LinearElement e = Oscillator(1, 0.7);
  double coarse = StepError(e, 0.01, kImplicitFast);
  double fine = StepError(e, 0.005, kImplicitFast);
  EXPECT_NEAR(coarse / fine, 2, 0.1);
  // RK4 is fourth order
  EXPECT_NEAR(StepError(e, 0.02, mjINT_RK4) / StepError(e, 0.01, mjINT_RK4), 16, 2);
}

TEST(LinearStepTest, ThreeStepsAPeriodUnderImplicitfastIsTheIntegratorsMotion) {
  // stable (the damping is implicit) but off by half the step
  LinearElement e = Oscillator(3, 0.5);
  EXPECT_FALSE(Diverges(e, 1, kImplicitFast));
  EXPECT_GT(StepError(e, 1, kImplicitFast), 0.4);
}

TEST(LinearStepTest, AnOverdampedServosCollapsedFastModeIsFine) {
  // kp 1, kv 1 on 1e-6: the fast mode lasts 1 us, the slow one 1 s; at h = 1 ms implicitfast
  // follows the slow mode, explicit Euler diverges
  LinearElement e{1e-6, 1, 1, 1};
  EXPECT_LT(StepError(e, 1e-3, kImplicitFast), 2e-3);
  LinearElement explicit_kv = e;
  explicit_kv.implicit_damping = 0;
  EXPECT_TRUE(Diverges(explicit_kv, 1e-3, mjINT_EULER));
  EXPECT_EQ(StepError(explicit_kv, 1e-3, mjINT_EULER), INFINITY);
}

TEST(LinearStepTest, AnUndampedSpringPastTwoOverOmegaDiverges) {
  // semi-implicit Euler keeps an undamped oscillator bounded while omega h < 2
  LinearElement e = Oscillator(1, 0);
  double omega = 2 * kPi;
  EXPECT_FALSE(Diverges(e, 1.9 / omega, mjINT_EULER));
  EXPECT_TRUE(Diverges(e, 2.1 / omega, mjINT_EULER));
}

TEST(LinearStepTest, ADamperIsJudgedOnItsVelocityStep) {
  // a velocity servo, kv 1 on 1: damping time 1 s. At h = 1 s implicitfast's v_n = 2^-n
  // against e^-n, worst at the first step; at 1 ms it is resolved
  LinearElement e{1, 0, 1, 1};
  EXPECT_LT(StepError(e, 1e-3, kImplicitFast), 1e-3);
  EXPECT_NEAR(StepError(e, 1, kImplicitFast), 0.5 - std::exp(-1.0), 1e-12);
}

TEST(LinearStepTest, TheBisectionsMeetTheBound) {
  LinearElement e = Oscillator(3e-3, 0.3);  // 3 ms period at h = 1 ms
  double h = 1e-3, bound = 0.1;
  ASSERT_GT(StepError(e, h, kImplicitFast), bound);
  double step = TimestepFor(e, h, kImplicitFast, bound);
  ASSERT_GT(step, 0);
  EXPECT_LE(StepError(e, step, kImplicitFast), bound);
  EXPECT_GT(StepError(e, step * 1.05, kImplicitFast), bound);
  double inertia = InertiaFor(e, h, kImplicitFast, bound);
  ASSERT_TRUE(std::isfinite(inertia));
  LinearElement heavier = e;
  heavier.inertia = inertia;
  EXPECT_LE(StepError(heavier, h, kImplicitFast), bound);
  heavier.inertia = inertia / 1.05;
  EXPECT_GT(StepError(heavier, h, kImplicitFast), bound);
}

}  // namespace
}  // namespace plumb::audit
