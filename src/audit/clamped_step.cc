// A saturating position servo's step response under MuJoCo's integrators against the exact
// motion (clamped_step.h). The exact motion is piecewise closed-form: inside the force limits
// the linear element's matrix exponential (linear_step.h), at a limit a constant force on the
// inertia with the joint damping.

#include "audit/clamped_step.h"

#include <mujoco/mujoco.h>

#include <algorithm>
#include <cmath>

#include "audit/linear_step.h"

namespace plumb::audit {
namespace {

// The servo's force at (x, v) after both clamps, and whether a clamp that drops kv's derivative
// holds it (MuJoCo's test for forcerange: the clamped force at or beyond a bound; the same for
// the joint's clamp where it drops it).
double Force(const ClampedServo& s, double x, double v, bool* drops_kv) {
  double f = std::clamp(-s.kp * x - s.kv * v, s.force_lo, s.force_hi);
  double g = std::clamp(f, s.joint_lo, s.joint_hi);
  if (drops_kv) {
    *drops_kv = f <= s.force_lo || f >= s.force_hi ||
                (s.joint_clamp_drops_kv && (g <= s.joint_lo || g >= s.joint_hi));
  }
  return g;
}

// The force the step starts against while saturated, the smaller of the two directions.
double Limit(const ClampedServo& s) {
  return std::min({s.force_hi, s.joint_hi, -s.force_lo, -s.joint_lo});
}

// One step of the integrator's map.
void Discrete(const ClampedServo& s, double h, int integrator, double* x, double* v) {
  auto accel = [&s](double px, double pv) {
    return (Force(s, px, pv, nullptr) - s.damping * pv) / s.inertia;
  };
  if (integrator == mjINT_RK4) {
    double k1x = *v, k1v = accel(*x, *v);
    double k2x = *v + 0.5 * h * k1v, k2v = accel(*x + 0.5 * h * k1x, k2x);
    double k3x = *v + 0.5 * h * k2v, k3v = accel(*x + 0.5 * h * k2x, k3x);
    double k4x = *v + h * k3v, k4v = accel(*x + h * k3x, k4x);
    *x += h / 6 * (k1x + 2 * k2x + 2 * k3x + k4x);
    *v += h / 6 * (k1v + 2 * k2v + 2 * k3v + k4v);
    return;
  }
  bool saturated = false;
  double f = Force(s, *x, *v, &saturated) - s.damping * *v;
  // implicit and implicitfast (every integrator but Euler here; 2.2.2 has no implicitfast)
  bool kv_implicit = integrator != mjINT_EULER && !saturated;
  double implicit = s.implicit_damping + (kv_implicit ? s.kv : 0);
  *v += h * f / (s.inertia + h * implicit);
  *x += h * *v;
}

// The exact motion over dt from (x, v), linear or saturated as it starts.
class ExactFlow {
 public:
  ExactFlow(const ClampedServo& s, double dt)
      : s_(s), dt_(dt), linear_(Exact({s.inertia, s.kp, s.kv + s.damping, 0}, dt)) {
    rate_ = s.damping / s.inertia;
    decay_ = std::exp(-rate_ * dt);
  }
  void Flow(double* x, double* v) const {
    double free = -s_.kp * *x - s_.kv * *v;
    double f = Force(s_, *x, *v, nullptr);
    if (f == free) {
      double x1 = linear_[0] * *x + linear_[1] * *v, v1 = linear_[2] * *x + linear_[3] * *v;
      *x = x1, *v = v1;
    } else if (rate_ > 0) {
      double terminal = f / s_.damping;
      *x += terminal * dt_ + (*v - terminal) * (1 - decay_) / rate_;
      *v = terminal + (*v - terminal) * decay_;
    } else {
      *x += *v * dt_ + 0.5 * f / s_.inertia * dt_ * dt_;
      *v += f / s_.inertia * dt_;
    }
  }

 private:
  const ClampedServo& s_;
  double dt_;
  Mat linear_;
  double rate_, decay_;
};

// The time the step takes to arrive: the linear element's settling time, plus the travel
// under the limit (bang-bang, or at the velocity the joint damping lets it reach).
double ArrivalTime(const ClampedServo& s) {
  double settle = SettleTime({s.inertia, s.kp, s.kv + s.damping, 0});
  double limit = Limit(s);
  double travel = limit > 0 ? 4 * std::sqrt(s.step * s.inertia / limit) + s.step * s.damping / limit
                            : 0;
  return settle + travel;
}

}  // namespace

bool Saturates(const ClampedServo& s) { return s.kp * s.step > Limit(s); }

double ClampedStepError(const ClampedServo& s, double h, int integrator, int substeps) {
  if (!(s.inertia > 0) || !(s.step > 0)) return 0;
  ExactFlow exact(s, h / substeps);
  double x = -s.step, v = 0, rx = -s.step, rv = 0, worst = 0;
  for (int n = HorizonSteps(ArrivalTime(s), h); n > 0; --n) {
    Discrete(s, h, integrator, &x, &v);
    for (int k = 0; k < substeps; ++k) exact.Flow(&rx, &rv);
    double err = std::fabs(x - rx) / s.step;
    if (!std::isfinite(err) || err > 1e6) return INFINITY;
    worst = std::max(worst, err);
  }
  return worst;
}

double ClampedTimestepFor(const ClampedServo& s, double h, int integrator, double bound) {
  return LogBisect([&](double step) { return ClampedStepError(s, step, integrator); }, h,
                   h * 1e-6, bound, 30);
}

double ClampedInertiaFor(const ClampedServo& s, double h, int integrator, double bound) {
  auto error = [&](const ClampedServo& x) { return ClampedStepError(x, h, integrator); };
  return InertiaBisect(s, error, bound, 30);
}

}  // namespace plumb::audit
