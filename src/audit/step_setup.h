// A step response as audit_step.cc runs and judges it and step_setup.cc prepares it: what
// moves with the driven actuator, a position servo's joint or tendon and its range, and the
// ctrl step with the joints held still. Private to the audit.

#ifndef PLUMB_SRC_AUDIT_STEP_SETUP_H_
#define PLUMB_SRC_AUDIT_STEP_SETUP_H_

#include <mujoco/mujoco.h>

#include <cmath>
#include <optional>
#include <vector>

#include "audit/audit_layers.h"
#include "core/joint_size.h"

namespace plumb::audit {

// What moves with actuator u: the joints its moment reaches (a tendon's, all of them), and
// every joint an active equality ties to one of those, until none is added; and the
// equalities that tie them.
struct Coupling {
  std::vector<bool> driven;      // njnt: the joints its moment reaches
  std::vector<bool> joints;      // njnt: those and the joints tied to them
  std::vector<bool> equalities;  // neq
};

// What a position servo moves, in that thing's units (actuator length / gear): a hinge or
// slide, or a fixed tendon, and its range (a tendon without one: its joints' ranges through
// its coefficients; infinite where nothing bounds it).
struct Reach {
  int obj = mjOBJ_JOINT, id = -1;
  double lo = -INFINITY, hi = INFINITY;
  const char* unit = "rad";
};

// The ctrl step: from `before` to `after` (ctrl units), what it is measured in, and for a
// servo where it should end (`goal`, in the measured quantity's units).
struct CtrlStep {
  ActuatorKind kind = ActuatorKind::kOther;
  double before = 0, after = 0;
  double goal = NAN;
  double length0 = 0;           // the actuator length before the step
  int ctrl = 0, out = 0;        // its control and force output (ActuatorCtrl, ActuatorOutput)
  std::vector<int> held;        // joints held at the reference pose (qpos, qvel reset every step)
  std::vector<mjtNum> qpos;     // the reference pose
  Coupling moving;              // what moves with the actuator (a servo's)
  std::optional<Reach> reach;   // a position servo's joint or tendon
  double from = NAN, to = NAN;  // its step there, in the reach's units
  double Quantity(const mjData* d) const {
    switch (kind) {
      case ActuatorKind::kPositionServo:
        return d->actuator_length[out];
      case ActuatorKind::kVelocityServo:
        return d->actuator_velocity[out];
      default:
        return d->actuator_force[out];
    }
  }
  // Puts the held joints back at the reference pose, at rest.
  void Hold(const mjModel* m, mjData* d) const {
    for (int j : held) {
      int q = m->jnt_qposadr[j], v = m->jnt_dofadr[j];
      for (int k = 0; k < internal::JointQposSize(m->jnt_type[j]); ++k)
        d->qpos[q + k] = qpos[q + k];
      for (int k = 0; k < internal::JointDofSize(m->jnt_type[j]); ++k) d->qvel[v + k] = 0;
    }
  }
};

// Resets `data` to the reference pose with every other servo holding it and other ctrls at
// the middle of their range; when u is a servo, every joint that neither a position servo nor
// u moves (with what an equality or tendon ties to u's joints) is held there kinematically
// (its qpos and qvel put back before every step). Then chooses u's step (ChooseStep).
CtrlStep PrepareStep(Model& work, Data& data, const std::vector<Assignment>& sets,
                     const ReferencePose& ref, int u);

}  // namespace plumb::audit

#endif  // PLUMB_SRC_AUDIT_STEP_SETUP_H_
