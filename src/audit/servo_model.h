// Servos as the actuator layer's stability and time-scale checks read them (audit_servo.cc,
// audit_timescale.cc): along its transmission each is a spring (kp) and a damper (kv) on the
// inertia it moves, with the joint damping along that transmission. Private to the audit.

#ifndef PLUMB_SRC_AUDIT_SERVO_MODEL_H_
#define PLUMB_SRC_AUDIT_SERVO_MODEL_H_

#include <optional>
#include <vector>

#include "plumb/model.h"

namespace plumb::audit {

struct Servo {
  double kp = 0, kv = 0;  // actuator space: force per unit of length and of velocity
  double inertia = 0;     // actuator space: 1 / (m^T M^-1 m)
  double damping = 0;     // actuator space: joint damping along the transmission, 1 / sum(m_i^2/d_i)
  bool damping_implicit = false;  // the integrator treats `damping` implicitly
  // The damping the integrator treats implicitly (Euler with eulerdamp, the implicit ones).
  double ImplicitDamping() const { return damping_implicit ? damping : 0; }
};

enum class Scheme { kEuler, kImplicit, kRk4 };
Scheme SchemeOf(int integrator);

// How many times the integrator's stability limit exceeds the servo's side (below 1 it
// diverges), at timestep h (audit_servo.cc explains the bounds).
double Margin(const Servo& s, double h, Scheme scheme);

// A fixed-gain actuator (or MuJoCo's native pid) with an affine bias that feeds back its length
// (kp) or velocity (kv), read at d's pose (after mj_forward); nullopt for any other actuator.
std::optional<Servo> ServoGains(const mjModel* m, const mjData* d, int u);

// The inertia 1 / (m^T M^-1 m) along the generalized-force direction `moment` (length nv) at
// d's pose, with the dof damping along it (1 / sum(m_i^2 / d_i): none when a dof it moves has
// none) and whether the integrator treats that damping implicitly. False when M^-1 sees no
// motion along `moment`.
bool AlongTransmission(const mjModel* m, const mjData* d, const std::vector<mjtNum>& moment,
                       Servo* s);

// Whether an equality constraint ties joint j to another joint: then the link the servo moves
// is not free, which the linear models do not model.
bool Coupled(const mjModel* m, int j);

}  // namespace plumb::audit

#endif  // PLUMB_SRC_AUDIT_SERVO_MODEL_H_
