// A saturating servo's step response under MuJoCo's integrators against the exact motion
// (src/audit/clamped_step.h), on the case MuJoCo shows: the UR5e's wrist_3 without armature
// (I 1.3e-4 kg*m^2, kp 500, kv 100, forcerange +-28 N*m) chatters under implicitfast at 2 ms on
// a 1.26 rad step (MuJoCo 4.0: 130 % of the step between h and h/20) because the saturated
// steps take kv explicitly (under a joint's actuatorfrcrange too); with the armature or
// without the clamp it is fine. The exact reference has converged in its
// substeps, and the bisections' armature and timestep meet the bound.

#include "audit/clamped_step.h"

#include <gtest/gtest.h>
#include <mujoco/mujoco.h>

#include <cmath>

#include "audit/linear_step.h"

namespace plumb::audit {
namespace {

constexpr int kImplicit = mjINT_IMPLICIT;  // implicitfast steps one joint alike

ClampedServo Wrist(double armature) {
  ClampedServo s;
  s.inertia = 1.32e-4 + armature;
  s.kp = 500, s.kv = 100;
  s.force_lo = -28, s.force_hi = 28;
  s.step = 1.2566;
  return s;
}

TEST(ClampedStepTest, AWristWithoutArmatureChattersWhenItsForceSaturates) {
  ClampedServo s = Wrist(0);
  EXPECT_TRUE(Saturates(s));
  EXPECT_GT(ClampedStepError(s, 0.002, kImplicit), 1.0);
  // the same servo unclamped is the linear element, resolved by implicitfast
  ClampedServo free = s;
  free.force_lo = -INFINITY, free.force_hi = INFINITY;
  EXPECT_FALSE(Saturates(free));
  EXPECT_LT(ClampedStepError(free, 0.002, kImplicit), 0.01);
  EXPECT_LT(StepError({s.inertia, s.kp, s.kv, s.kv}, 0.002, kImplicit), 0.01);
}

TEST(ClampedStepTest, AJointsClampDropsKvToo) {
  // MuJoCo 4.0.0 and 4.0.1 with the wrist's forcerange moved to the joint's actuatorfrcrange: the
  // same period-2 cycle, 130 % of the step between h and h/20
  ClampedServo s = Wrist(0);
  s.joint_lo = s.force_lo, s.joint_hi = s.force_hi;
  s.force_lo = -INFINITY, s.force_hi = INFINITY;
  EXPECT_TRUE(Saturates(s));
  EXPECT_GT(ClampedStepError(s, 0.002, kImplicit), 1.0);
}

TEST(ClampedStepTest, MuJoCo3KeepsKvUnderAJointsClamp) {
  // MuJoCo 3.11 keeps kv implicit under actuatorfrcrange: no cycle, the velocity ramps by F/kv a
  // step (one hinge of this inertia in MuJoCo 3.11: 8.4 % of the step between h and h/20, whose
  // own ramp lags too; the exact motion is further)
  ClampedServo s = Wrist(0);
  s.joint_lo = s.force_lo, s.joint_hi = s.force_hi;
  s.force_lo = -INFINITY, s.force_hi = INFINITY;
  s.joint_clamp_drops_kv = false;
  double error = ClampedStepError(s, 0.002, kImplicit);
  EXPECT_GT(error, 0.05);
  EXPECT_LT(error, 0.3);
}

TEST(ClampedStepTest, TheMenagerieArmatureResolvesIt) {
  EXPECT_LT(ClampedStepError(Wrist(0.1), 0.002, kImplicit), 0.01);
}

TEST(ClampedStepTest, TheReferenceHasConverged) {
  for (double armature : {0.0, 0.001, 0.1}) {
    ClampedServo s = Wrist(armature);
    for (int integrator : {int(mjINT_EULER), int(mjINT_RK4), kImplicit}) {
      double h = integrator == kImplicit ? 0.002 : 1e-7;  // explicit Euler needs h < 2 I / kv
      double coarse = ClampedStepError(s, h, integrator, 64);
      double fine = ClampedStepError(s, h, integrator, 512);
      if (std::isinf(coarse)) continue;
      EXPECT_NEAR(coarse, fine, 0.005 + 0.01 * fine) << armature << " " << integrator;
    }
  }
}

TEST(ClampedStepTest, AResolvedServoIsOffByLittle) {
  ClampedServo s = Wrist(0.1);
  EXPECT_LT(ClampedStepError(s, 1e-4, kImplicit), 0.01);
  EXPECT_LT(ClampedStepError(s, 1e-4, mjINT_RK4), 0.001);
}

TEST(ClampedStepTest, TheBisectionsMeetTheBound) {
  ClampedServo s = Wrist(0);
  double inertia = ClampedInertiaFor(s, 0.002, kImplicit, 0.1);
  ASSERT_TRUE(std::isfinite(inertia));
  EXPECT_GT(inertia, s.inertia);
  ClampedServo heavier = s;
  heavier.inertia = inertia;
  EXPECT_LE(ClampedStepError(heavier, 0.002, kImplicit), 0.1);
  double h = ClampedTimestepFor(s, 0.002, kImplicit, 0.1);
  ASSERT_GT(h, 0);
  EXPECT_LT(h, 0.002);
  EXPECT_LE(ClampedStepError(s, h, kImplicit), 0.1);
}

}  // namespace
}  // namespace plumb::audit
