// Physics we can solve by hand, to hold simulations against.
//
// Units are SI throughout: s, m, kg, rad, N*m*s/rad.
//
// Example (the chapter's pendulum):
//   plumb::PendulumParams p = *plumb::DetectPendulum(model);   // I, m*g*d, c from the model
//   double t0 = plumb::SmallAnglePeriod(p);                      // 2*pi*sqrt(I/(m*g*d))
//   double t = plumb::LargeAnglePeriod(p, 0.7);                 // with the elliptic integral
//
// Thread-safety: every function may be called from several threads at once, also on one Model:
// a Model is only read (DetectPendulum computes on a Data of its own) and nothing keeps state.

#ifndef PLUMB_INCLUDE_PLUMB_ANALYTIC_H_
#define PLUMB_INCLUDE_PLUMB_ANALYTIC_H_

#include <optional>
#include <string>
#include <vector>

#include "plumb/model.h"

namespace plumb {

// The complete elliptic integral of the first kind K(k) = int_0^{pi/2} dphi /
// sqrt(1 - k^2 sin^2 phi), for modulus 0 <= k < 1, by the arithmetic-geometric mean
// (relative error ~1e-16). @throws ValueError for k outside [0, 1).
double EllipticK(double k);

// A rigid body swinging on one hinge under gravity, as compiled.
struct PendulumParams {
  int joint = -1;          // the hinge's joint id
  double inertia = 0;      // I: moment of inertia about the hinge axis incl. armature, kg*m^2
  double stiffness = 0;    // m*g*d: gravity torque per rad at small angles, N*m/rad
  double damping = 0;      // c: viscous damping of the hinge, N*m*s/rad
  double mass = 0;         // m: mass of everything the hinge moves, kg
  double distance = 0;     // d: distance of their centre of mass from the axis, m
  double gravity = 0;      // g: gravity perpendicular to the axis, m/s^2
  double equilibrium = 0;  // hinge angle at which the centre of mass hangs below the axis, rad
};

// Recognises a single hinge under gravity from the compiled model (not from names):
// exactly one joint, an unlimited hinge, no spring, dry friction, equality constraints,
// tendons or fluid forces, no actuator that pushes at ctrl = 0 (a plain motor is fine),
// gravity enabled with a component perpendicular to the axis, the centre of mass off the
// axis, and no geom it can collide with within reach of a full turn. Returns the parameters, or
// nullopt with the reason in `why_not`. Uses mj_fullM at the equilibrium angle for I.
// @throws MujocoError.
std::optional<PendulumParams> DetectPendulum(const Model& model, std::string* why_not = nullptr);

// Why some actuator applies force while every ctrl is 0 (a position or velocity servo's
// bias, a muscle's passive force), or "" when none does: with ctrl = 0 a plain motor
// leaves the system passive. A plugin actuator (mujoco.pid) counts as pushing: its force is
// the plugin's.
std::string ActuatorPushingAtZeroControl(const Model& model);

// Small-angle period T0 = 2*pi*sqrt(I / (m*g*d)), s (undamped).
double SmallAnglePeriod(const PendulumParams& p);

// Exact undamped period for amplitude theta0 (rad, |theta0| < pi):
// T = T0 * (2/pi) * K(sin(theta0/2)). @throws ValueError for |theta0| >= pi.
double LargeAnglePeriod(const PendulumParams& p, double theta0);

// How a linear oscillator with ratio zeta returns to rest.
enum class DampingClass { kUndamped, kUnderdamped, kCritical, kOverdamped };
const char* DampingClassName(DampingClass c);

struct DampingAnalysis {
  double zeta = 0;           // damping ratio c / (2*sqrt(I*m*g*d))
  double omega0 = 0;         // natural angular frequency sqrt(m*g*d / I), rad/s
  double omega_d = 0;        // damped angular frequency omega0*sqrt(1 - zeta^2), 0 if none
  double damped_period = 0;  // 2*pi/omega_d, s; 0 when not oscillating
  DampingClass kind = DampingClass::kUndamped;
};

// Linearised damping analysis. |zeta - 1| <= critical_band counts as critical.
DampingAnalysis AnalyseDamping(double inertia, double stiffness, double damping,
                               double critical_band = 1e-3);

// Mean period of a sampled signal, from linearly interpolated upward crossings of
// `level` (s). Needs at least two upward crossings; returns nullopt otherwise.
// `max_periods` (> 0) stops after that many full periods.
std::optional<double> PeriodFromCrossings(const std::vector<double>& t,
                                          const std::vector<double>& x, double level = 0,
                                          int max_periods = 0);

// Local maxima of x (strictly above both neighbours' plateau), in time order.
std::vector<double> Peaks(const std::vector<double>& x);

}  // namespace plumb

#endif  // PLUMB_INCLUDE_PLUMB_ANALYTIC_H_
