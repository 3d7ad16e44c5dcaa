// A position servo whose force saturates, I x'' = clamp(-kp x - kv v) - d v, stepped as
// MuJoCo's integrators step it against the exact motion (audit_timescale.cc). Under implicit
// and implicitfast MuJoCo solves kv implicitly only while the servo's force is inside its
// clamp: mjd_actuator_vel (engine_derivative.c) skips an actuator whose force sits at its
// forcerange, so in the saturated steps the servo's damping is explicit. A joint's
// actuatorfrcrange (clampVec on qfrc_actuator in mj_fwdActuation, after the actuator's own
// clamp) does the same in MuJoCo 4.0 as measured (a wrist step's first step moves h^2 F / I,
// kv's share gone) but not in 3.11 (compat::kJointClampDropsActuatorDerivative), though the
// engine source of August 2026 tests only forcerange; the model follows the measurement.
// Private to the audit.

#ifndef PLUMB_SRC_AUDIT_CLAMPED_STEP_H_
#define PLUMB_SRC_AUDIT_CLAMPED_STEP_H_

#include <cmath>

namespace plumb::audit {

// Along the servo's transmission, in actuator units.
struct ClampedServo {
  double inertia = 0;           // I > 0
  double kp = 0, kv = 0;        // the servo's gains
  double damping = 0;           // d: joint damping along the transmission
  double implicit_damping = 0;  // the part of d the integrator solves implicitly
  // MuJoCo's actuator forcerange and the joint's actuatorfrcrange seen in actuator units; +-inf
  // when none. kv's derivative is dropped while forcerange holds the force, and while the
  // joint's clamp does when joint_clamp_drops_kv.
  double force_lo = -INFINITY, force_hi = INFINITY;
  double joint_lo = -INFINITY, joint_hi = INFINITY;
  bool joint_clamp_drops_kv = true;
  double step = 0;  // the step: x from -step to rest at 0, step > 0
};

// Whether the step saturates the force in the exact motion: kp * step beyond either clamp.
bool Saturates(const ClampedServo& s);

// The largest |x_discrete - x_exact| at the steps, relative to the step, over a horizon long
// enough to arrive (the linear element's settling time plus the saturated travel, 10 to
// 100000 steps). The discrete map is the integrator's: mjINT_RK4 classic RK4 on the clamped
// ODE; Euler v' = v + h f / (I + h d_implicit); implicit and implicitfast the same with kv
// added to the implicit part in the steps where no clamp that drops it holds the force. The
// exact motion is flowed in closed form over `substeps` pieces per step, each piece linear or
// saturated as it starts. +inf when the discrete motion runs away (beyond 1e6 steps).
double ClampedStepError(const ClampedServo& s, double h, int integrator, int substeps = 64);

// The largest timestep (below h) and the smallest inertia (above s.inertia) at which
// ClampedStepError is at most `bound`, by bisection on the logarithm: 0 (timestep) or +inf
// (inertia) when none within 1e-6 h or 1e8 I is.
double ClampedTimestepFor(const ClampedServo& s, double h, int integrator, double bound);
double ClampedInertiaFor(const ClampedServo& s, double h, int integrator, double bound);

}  // namespace plumb::audit

#endif  // PLUMB_SRC_AUDIT_CLAMPED_STEP_H_
