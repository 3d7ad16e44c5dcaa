// The unit step response of a linear element, I x'' + c x' + k x = 0, as MuJoCo's integrators
// step it, against the exact one: how much of a servo's or spring's motion is the integrator's
// (audit_timescale.cc). Private to the audit.

#ifndef PLUMB_SRC_AUDIT_LINEAR_STEP_H_
#define PLUMB_SRC_AUDIT_LINEAR_STEP_H_

#include <array>
#include <functional>

namespace plumb::audit {

using Mat = std::array<double, 4>;  // row-major 2x2

// A spring and a damper on an inertia, along one direction (a servo's transmission, a joint,
// a tendon), in consistent units.
struct LinearElement {
  double inertia = 0;    // I > 0
  double stiffness = 0;  // k >= 0; 0 for a damper (a velocity servo)
  double damping = 0;    // c >= 0, all of it
  // The part of c the Euler-type maps solve implicitly: (I + h c_implicit) (v' - v) = h f.
  double implicit_damping = 0;

  // Its time scales, s: the period 2 pi sqrt(I / k) and the damping time I / c; +inf without
  // a spring or a damper.
  double Period() const;
  double DampingTime() const;
};

// The number of steps of h in `seconds`, from 10 to 100000: the horizon a step response is
// judged over.
int HorizonSteps(double seconds, double h);

// The exact map of (x, v) over time t: exp(A t), A = [0 1; -k/I -c/I] (clamped_step.cc
// flows the unsaturated stretches of its reference with it).
Mat Exact(const LinearElement& e, double t);

// The integrator's discrete map of the element: mjINT_RK4 steps the ODE with classic RK4,
// every other integer with the Euler-type map (semi-implicit Euler, implicit, implicitfast),
// v' = v + h (-k x - c v) / (I + h c_implicit), x' = x + h v'.
//
// The largest |x_discrete - x_exact| at the steps over a horizon long enough to settle (four
// of its slowest time scales, at most five periods, 10 to 100000 steps), relative to the unit
// step: x from -1 to rest at 0 (for k = 0, the velocity from -1 to 0). 0 for an element with
// neither stiffness nor damping; +inf when the discrete map diverges over the horizon.
double StepError(const LinearElement& e, double h, int integrator);

// The time over which the step response settles: four of its slowest time scales, at most
// five periods.
double SettleTime(const LinearElement& e);

// Whether the discrete map grows (spectral radius above 1): the integrator diverges.
bool Diverges(const LinearElement& e, double h, int integrator);

// The value nearest `from`, on the way to `to` (either direction), at which error(value) is at
// most `bound`, by bisection on the logarithm: `from` when it already is; 0 (to below from) or
// +inf (to above) when `to` is not. The error is taken to cross the bound once between them.
double LogBisect(const std::function<double(double)>& error, double from, double to,
                 double bound, int iterations);

// The smallest inertia from e.inertia up to 1e8 times it at which error(element with that
// inertia) is at most `bound` (LogBisect); +inf when none is.
template <class Element, class Error>
double InertiaBisect(const Element& e, const Error& error, double bound, int iterations) {
  Element heavier = e;
  auto at = [&](double inertia) {
    heavier.inertia = inertia;
    return error(heavier);
  };
  return LogBisect(at, e.inertia, e.inertia * 1e8, bound, iterations);
}

// The largest timestep (below h) at which StepError is at most `bound`, by bisection on
// log h; 0 when none above h / 1e6 is.
double TimestepFor(const LinearElement& e, double h, int integrator, double bound);

// The smallest inertia (above e.inertia) at which StepError at h is at most `bound`;
// +inf when none below 1e8 times it is.
double InertiaFor(const LinearElement& e, double h, int integrator, double bound);

}  // namespace plumb::audit

#endif  // PLUMB_SRC_AUDIT_LINEAR_STEP_H_
