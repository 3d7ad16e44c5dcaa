// A description of a compiled model: the chapter's tables (sizes, options, bodies,
// joints, actuators, sensors), every quantity with its unit, and the classification
// of what is a parameter, state, input or derived. `plumb inspect` prints it.
//
// Example:
//   plumb::ModelDescription d = plumb::Describe(model);
//   d.sizes  // {{"nbody", 2}, {"njnt", 1}, {"nq", 1}, {"nv", 1}, {"nu", 0}, ...}
//
// Thread-safety: Describe and ActuatorPositionUnit only read the model and keep no state: they
// may be called from several threads at once, also on one Model. They throw nothing of plumb's
// own (only std::bad_alloc).

#ifndef PLUMB_INCLUDE_PLUMB_DESCRIBE_H_
#define PLUMB_INCLUDE_PLUMB_DESCRIBE_H_

#include <array>
#include <string>
#include <utility>
#include <vector>

#include "plumb/model.h"

namespace plumb {

struct BodyDescription {
  int id = 0;
  std::string name;
  int parent = 0;                   // parent body id (world is 0 and its own parent)
  double mass = 0;                  // kg
  std::array<double, 3> com{};      // centre of mass in the body frame, m (body_ipos)
  std::array<double, 3> inertia{};  // principal moments of inertia about the com, kg*m^2
};

struct JointDescription {
  int id = 0;
  std::string name;
  std::string type;  // free, ball, slide, hinge
  int body = 0;
  int qposadr = 0, dofadr = 0;  // first index in qpos / qvel
  int nq = 1, nv = 1;           // number of qpos / qvel entries
  bool limited = false;
  std::array<double, 2> range{};  // rad (hinge) or m (slide), meaningful when limited
  double damping = 0;             // N*m*s/rad or N*s/m (first dof)
  double armature = 0;            // kg*m^2 or kg (first dof)
  double stiffness = 0;           // N*m/rad or N/m
  double frictionloss = 0;        // N*m or N (first dof)
  std::string position_unit;      // "rad", "m", or "m, quat" for free/ball blocks
};

struct ActuatorDescription {
  int id = 0;
  std::string name;
  std::string transmission;  // joint, tendon, site, ...
  std::string target;        // name of the joint/tendon/site it drives
  double gear = 1;           // first gear component
  bool ctrllimited = false;
  std::array<double, 2> ctrlrange{};
  bool forcelimited = false;
  std::array<double, 2> forcerange{};  // in force_unit
  // motor, position, velocity, intvelocity (a position servo behind an integrator: ctrl is a
  // velocity), muscle or general (from gain, bias and dynamics)
  std::string kind;
  // What ctrl means: "N*m" (motor on a hinge), "rad" (position servo), ... With a gear
  // other than 1 the actuator works in geared units: a motor's ctrl is "N*m/gear" (the
  // joint feels gear x ctrl) and a servo's "gear*rad" (it targets gear x the angle).
  std::string ctrl_unit;
  std::string force_unit;  // of the actuator force and forcerange: "N*m", "N", "N/gear", ...
  // The force or torque the joint (tendon) receives, gear x actuator force, bounded by a
  // motor's ctrlrange (times its gain), by forcerange and by its joint's actuatorfrcrange
  // (MuJoCo 3+; the bound of all the joint's actuators together); `joint_force_limited` is
  // false when none bounds it. In joint_force_unit: "N*m" on a hinge, "N" on a slide or a
  // tendon, "N, N*m" for site and body transmissions.
  bool joint_force_limited = false;
  std::array<double, 2> joint_force_range{};
  std::string joint_force_unit;
};

struct SensorDescription {
  int id = 0;
  std::string name;
  std::string type;  // accelerometer, jointpos, ...
  int adr = 0;       // first index in sensordata
  int dim = 1;       // number of sensordata entries
  std::string unit;  // of each entry: "m/s^2", "rad", "N", ... ("" when dimensionless)
};

// One row of the chapter's classification table.
struct RoleDescription {
  std::string role;        // parameter, state, input, derived
  std::string where;       // mjModel / mjData
  std::string examples;    // fields with this model's sizes, e.g. "qpos (nq=1)"
  std::string who_writes;  // who changes it, e.g. "you, before mj_forward"
};

// An actuator's or sensor's delay (MuJoCo 3.5+: delay="..." nsample="..."). MuJoCo keeps
// nsample past values, so it can delay by at most nsample x timestep: a longer delay is
// silently shortened to that.
struct DelayDescription {
  std::string kind;  // "actuator" or "sensor"
  int id = 0;
  std::string name;
  double delay = 0;   // as written, s
  long nsample = 0;   // history samples kept
  double buffer = 0;  // nsample x timestep, s: the longest delay MuJoCo applies
  long needed_nsample = 0;  // the nsample that covers `delay`
  bool shortened() const { return delay > buffer * (1 + 1e-9); }
  // "actuator 'm' (id 0): delay 0.5 s is longer than its buffer ... ", or "" when covered.
  std::string Warning() const;
};

struct ModelDescription {
  std::string file;
  std::string model_name;
  std::vector<std::pair<std::string, long>> sizes;  // nbody, njnt, nq, nv, nu, na, ...
  double timestep = 0;                              // s
  std::string integrator;                           // Euler, RK4, implicit, ...
  std::array<double, 3> gravity{};                  // m/s^2
  std::vector<BodyDescription> bodies;
  std::vector<JointDescription> joints;
  std::vector<ActuatorDescription> actuators;
  std::vector<SensorDescription> sensors;
  std::vector<DelayDescription> delays;  // every delayed actuator, then every delayed sensor
  std::vector<RoleDescription> roles;
  double total_mass = 0;  // kg
};

// Describes `model` as compiled.
ModelDescription Describe(const Model& model);

// The delayed actuators and sensors of `model` (Describe's `delays`, without the rest).
std::vector<DelayDescription> Delays(const Model& model);

// The unit of the position of what actuator `actuator` drives: "rad" for a hinge, "m" for
// a slide or a tendon, "m, rad" for site and body transmissions. The actuator length is
// gear x that position. `actuator` must be in [0, nu).
std::string ActuatorPositionUnit(const mjModel* m, int actuator);

}  // namespace plumb

#endif  // PLUMB_INCLUDE_PLUMB_DESCRIBE_H_
