// The unit step response of a linear element, I x'' + c x' + k x = 0, as MuJoCo's integrators
// step it, against the exact one: how much of a servo's or spring's motion is the integrator's
// (audit_timescale.cc). Private to the audit.

#ifndef PLUMB_SRC_AUDIT_LINEAR_STEP_H_
#define PLUMB_SRC_AUDIT_LINEAR_STEP_H_

namespace plumb::audit {

// A spring and a damper on an inertia, along one direction (a servo's transmission, a joint,
// a tendon), in consistent units.
struct LinearElement {
  double inertia = 0;    // I > 0
  double stiffness = 0;  // k >= 0; 0 for a damper (a velocity servo)
  double damping = 0;    // c >= 0, all of it
  // The part of c the Euler-type maps solve implicitly: (I + h c_implicit) (v' - v) = h f.
  double implicit_damping = 0;
};

// The integrator's discrete map of the element: mjINT_RK4 steps the ODE with classic RK4,
// every other integer with the Euler-type map (semi-implicit Euler, implicit, implicitfast),
// v' = v + h (-k x - c v) / (I + h c_implicit), x' = x + h v'.
//
// The largest |x_discrete - x_exact| at the steps over a horizon long enough to settle (four
// of its slowest time scales, at most five periods, 10 to 100000 steps), relative to the unit
// step: x from -1 to rest at 0 (for k = 0, the velocity from -1 to 0). 0 for an element with
// neither stiffness nor damping; +inf when the discrete map diverges over the horizon.
double StepError(const LinearElement& e, double h, int integrator);

// Whether the discrete map grows (spectral radius above 1): the integrator diverges.
bool Diverges(const LinearElement& e, double h, int integrator);

// The largest timestep (below h) at which StepError is at most `bound`, by bisection on
// log h; 0 when none above h / 1e6 is.
double TimestepFor(const LinearElement& e, double h, int integrator, double bound);

// The smallest inertia (above e.inertia) at which StepError at h is at most `bound`;
// +inf when none below 1e8 times it is.
double InertiaFor(const LinearElement& e, double h, int integrator, double bound);

}  // namespace plumb::audit

#endif  // PLUMB_SRC_AUDIT_LINEAR_STEP_H_
