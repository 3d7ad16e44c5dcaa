// The unit step response of a linear element under MuJoCo's integrators, against the exact
// one: both are 2x2 linear maps of (x, v) per step, the exact one the matrix exponential of
// A = [0 1; -k/I -c/I] over h.

#include "audit/linear_step.h"

#include <mujoco/mujoco.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <functional>

namespace plumb::audit {
namespace {

constexpr int kMinSteps = 10, kMaxSteps = 100000;
constexpr double kPi = 3.14159265358979323846;

Mat Mul(const Mat& a, const Mat& b) {
  return {a[0] * b[0] + a[1] * b[2], a[0] * b[1] + a[1] * b[3], a[2] * b[0] + a[3] * b[2],
          a[2] * b[1] + a[3] * b[3]};
}

}  // namespace

// exp(A h) in closed form, from A's eigenvalues s +- q (s = trace / 2).
Mat Exact(const LinearElement& e, double h) {
  double det = e.stiffness / e.inertia, s = -0.5 * e.damping / e.inertia;
  double disc = s * s - det;
  Mat shifted = {-s, 1, -det, s};  // A - s I
  if (disc >= 0 && std::sqrt(disc) * h >= 1) {
    // well separated real eigenvalues: (e^{l1 h} (A - l2) - e^{l2 h} (A - l1)) / (l1 - l2),
    // l1 from det / l2 without cancellation
    double l2 = s - std::sqrt(disc), l1 = det / l2;
    double e1 = std::exp(l1 * h), e2 = std::exp(l2 * h), span = l1 - l2;
    Mat a = {0, 1, -det, 2 * s};
    return {(e1 * (a[0] - l2) - e2 * (a[0] - l1)) / span, (e1 - e2) * a[1] / span,
            (e1 - e2) * a[2] / span, (e1 * (a[3] - l2) - e2 * (a[3] - l1)) / span};
  }
  // e^{s h} (c I + g (A - s I)): cosh / sinh(q h) / q, or cos / sin(w h) / w
  double c, g;
  if (disc >= 0) {
    double q = std::sqrt(disc);
    c = std::cosh(q * h);
    g = q > 0 ? std::sinh(q * h) / q : h;
  } else {
    double w = std::sqrt(-disc);
    c = std::cos(w * h);
    g = std::sin(w * h) / w;
  }
  double f = std::exp(s * h);
  return {f * (c + g * shifted[0]), f * g * shifted[1], f * g * shifted[2],
          f * (c + g * shifted[3])};
}

namespace {

// The integrator's one-step map.
Mat Discrete(const LinearElement& e, double h, int integrator) {
  double k = e.stiffness / e.inertia, c = e.damping / e.inertia;
  if (integrator == mjINT_RK4) {
    // I + hA + (hA)^2/2 + (hA)^3/6 + (hA)^4/24, by Horner
    Mat ha = {0, h, -k * h, -c * h}, p = {1, 0, 0, 1};
    for (double n : {4.0, 3.0, 2.0, 1.0}) {
      Mat t = Mul(ha, p);
      p = {1 + t[0] / n, t[1] / n, t[2] / n, 1 + t[3] / n};
    }
    return p;
  }
  double j = e.inertia + h * e.implicit_damping;
  double vx = -h * e.stiffness / j, vv = 1 - h * e.damping / j;
  return {1 + h * vx, h * vv, vx, vv};
}

double SpectralRadius(const Mat& a) {
  double half = 0.5 * (a[0] + a[3]), det = a[0] * a[3] - a[1] * a[2];
  double disc = half * half - det;
  if (disc < 0) return std::sqrt(det);
  return std::fabs(half) + std::sqrt(disc);
}

}  // namespace

double LinearElement::Period() const {
  return stiffness > 0 ? 2 * kPi * std::sqrt(inertia / stiffness) : INFINITY;
}

double LinearElement::DampingTime() const { return damping > 0 ? inertia / damping : INFINITY; }

int HorizonSteps(double seconds, double h) {
  double steps = std::ceil(seconds / h);
  return static_cast<int>(std::clamp(steps, double(kMinSteps), double(kMaxSteps)));
}

double SettleTime(const LinearElement& e) {
  double det = e.stiffness / e.inertia, s = 0.5 * e.damping / e.inertia;
  if (e.stiffness <= 0) return 4 / (2 * s);  // four damping times I / c
  if (s * s < det) {
    double period = 2 * kPi / std::sqrt(det);
    return s > 0 ? std::min(4 / s, 5 * period) : 5 * period;
  }
  double slow = det / (s + std::sqrt(s * s - det));  // the slower real mode's rate
  return 4 / slow;
}

double StepError(const LinearElement& e, double h, int integrator) {
  if (!(e.inertia > 0) || (e.stiffness <= 0 && e.damping <= 0)) return 0;
  Mat exact = Exact(e, h), step = Discrete(e, h, integrator);
  // a position step for a spring, a velocity step for a damper
  int judged = e.stiffness > 0 ? 0 : 1;
  double x[2] = {-1, 0}, y[2] = {-1, 0};
  if (judged == 1) x[0] = y[0] = 0, x[1] = y[1] = -1;
  double worst = 0;
  for (int n = HorizonSteps(SettleTime(e), h); n > 0; --n) {
    double x0 = exact[0] * x[0] + exact[1] * x[1], x1 = exact[2] * x[0] + exact[3] * x[1];
    double y0 = step[0] * y[0] + step[1] * y[1], y1 = step[2] * y[0] + step[3] * y[1];
    x[0] = x0, x[1] = x1, y[0] = y0, y[1] = y1;
    double err = std::fabs((judged ? y1 - x1 : y0 - x0));
    if (!std::isfinite(err) || err > 1e6) return INFINITY;
    worst = std::max(worst, err);
  }
  return worst;
}

bool Diverges(const LinearElement& e, double h, int integrator) {
  return SpectralRadius(Discrete(e, h, integrator)) > 1 + 1e-9;
}

double LogBisect(const std::function<double(double)>& error, double from, double to,
                 double bound, int iterations) {
  double lo = std::log(from), hi = std::log(to);
  if (error(from) <= bound) return from;
  if (error(to) > bound) return to > from ? INFINITY : 0;
  for (int i = 0; i < iterations; ++i) {
    double mid = 0.5 * (lo + hi);
    (error(std::exp(mid)) <= bound ? hi : lo) = mid;
  }
  return std::exp(hi);
}

double TimestepFor(const LinearElement& e, double h, int integrator, double bound) {
  return LogBisect([&](double step) { return StepError(e, step, integrator); }, h, h * 1e-6,
                   bound, 50);
}

double InertiaFor(const LinearElement& e, double h, int integrator, double bound) {
  auto error = [&](const LinearElement& x) { return StepError(x, h, integrator); };
  return InertiaBisect(e, error, bound, 50);
}

}  // namespace plumb::audit
