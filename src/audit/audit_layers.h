// What the audit's layers share (src/audit/audit_*.cc): how a finding names an element,
// the reference pose, and the observed runs that the actuator, contact and behaviour layers
// judge. Private to the audit (src/audit/).

#ifndef PLUMB_SRC_AUDIT_AUDIT_LAYERS_H_
#define PLUMB_SRC_AUDIT_AUDIT_LAYERS_H_

#include <cmath>
#include <functional>
#include <string>
#include <utility>
#include <vector>

#include "plumb/audit.h"
#include "plumb/keyframe.h"
#include "plumb/model.h"
#include "plumb/path.h"
#include "plumb/run.h"

namespace plumb::audit {

struct BodySolids;  // body_shape.h

// Per-element rows are listed for up to this many elements; beyond, a summary row.
constexpr int kMaxListed = 60;

// Cost budget of one audit run, in dof-steps (steps x max(nv, 30)): about a second of
// compute on a laptop core, so each run of a big model is shortened, never skipped.
constexpr double kDofStepBudget = 4e5;

// Max |qvel| below which a model counts as at rest.
constexpr double kRestSpeed = 0.05;

CheckElement ElementOf(const Model& model, int obj, int id, const char* noun);

// The single joint actuator u drives, -1 for tendons, sites and bodies.
int DrivenJoint(const mjModel* m, int u);

// ElementLabel(ElementOf(...)), for rows that name several elements.
std::string Elem(const Model& model, int obj, int id, const char* noun);

// A row about one element. `measured` and `threshold` are the row's texts (the threshold a
// bound; "" for an informational row); `fix` is what to do about a WARN or FAIL, and for a
// PASS or SKIP what the row shows or why it was skipped (its explanation).
CheckRow Make(const char* layer, std::string check, const CheckElement& element,
              std::string measured, std::string threshold, CheckStatus status, std::string fix);

// A row about the whole model (`subject` "") or several elements (`subject` names them).
CheckRow Make(const char* layer, std::string check, std::string subject, std::string measured,
              std::string threshold, CheckStatus status, std::string fix);

// `row` with its measurement and the reference (the threshold) it is held against as numbers
// with units ({NaN, ""} where a row has none); its texts, status and fix stay as they are.
CheckRow WithNumbers(CheckRow row, Quantity measured, Quantity reference = {});

// When a check has more rows than `shown`, one row saying how many were listed.
void ListedNote(const char* layer, const char* check, const char* noun, int total,
                std::vector<CheckRow>* out, int shown = kMaxListed);

// |gravity|, 0 when <flag gravity="disable"/> switches it off.
double GravityNorm(const mjModel* m);

// Moving bodies: those not welded to the world.
bool Moves(const mjModel* m, int b);

// Volume of geom g (PrimitiveVolume), NaN when it is not a primitive.
double GeomVolume(const mjModel* m, int g);

// One audit run and what the layers read from it.
struct Observed {
  std::string label;  // "passive settle", "step response of actuator 'elbow' (id 3)"
  RunResult result;
  double duration = 0;
  double deepest = 0;  // deepest penetration relative to the smaller geom size
  std::string deepest_pair;
  double deepest_late = 0;  // the same over the last part of the run, once impacts are over
  std::string deepest_late_pair;
  double deepest_m = 0, deepest_soft = 0;  // the deepest contact in m, and its SoftDepth
  double deepest_late_m = 0;               // that contact's penetration in m
  double deepest_late_soft = 0;            // and the depth its softness explains (SoftDepth), in m
  int max_iterations = 0;
  long steps_at_limit = 0;
  double energy0 = 0, energy_max = -INFINITY, energy_end = 0;
  double max_speed_end = 0;    // max |qvel| at the end
  double support_ratio = NAN;  // contact normal force / weight at the end
  double max_slip = 0;         // tangential speed at contacts at the end
  std::string slip_pair;
  std::string repro;               // where AuditOptions::keep_diverged kept it ("" when not)
  std::vector<AuditCurve> curves;  // what it looked like over time (for --report)
};

// `wanted` s of simulated time, shortened for big models to the dof-step budget (at
// least 20 steps), as a whole number of timesteps.
double Duration(const mjModel* m, double wanted, double budget = kDofStepBudget);

// Hands a diverged run to options.keep_diverged; returns where it was kept ("" when the
// run did not diverge or nobody keeps it).
std::string KeepDiverged(const Model& work, const RunResult& run, const AuditOptions& options,
                         const std::string& label);

// What to do about a diverged audit run, after MuJoCo's reason.
std::string DivergedFix(const Observed& o);

// Runs `model` after `sets` from `ref` under `control` for `duration` s in four pieces;
// when `longest` > duration it goes on, a quarter of `duration` at a time, until the
// model is at rest or `longest` s have passed. Penetration "late" is over the last
// piece, once impacts are over.
Observed Observe(const Model& model, const std::vector<Assignment>& sets, const ReferencePose& ref,
                 double duration, const std::function<void(mjData*, double)>& control,
                 const AuditOptions& options, const std::string& label, double longest = 0);

// One row per delayed element of `kind` ("actuator" or "sensor"): WARN when its delay is
// longer than the nsample x timestep its history buffer holds (MuJoCo silently shortens it).
void DelayRows(const Model& model, const std::string& kind, const char* layer, const char* check,
               std::vector<CheckRow>* out);

// The layers, in the order the audit runs them; each appends its findings to `out` and
// the runs it made to `runs`.
void StructureLayer(const Model& model, std::vector<CheckRow>* out);
// structure.solref_clamp (audit_solref.cc): constraints whose standard solref timeconst MuJoCo's
// refsafe limit raises to 2 x timestep, a WARN row per kind of constraint, written timeconst
// and default class; one PASS row when none is, a SKIP when refsafe is disabled.
void SolrefClamps(const Model& model, std::vector<CheckRow>* out);
// The start the audit judges from (`data` after mj_forward there, `ref` its reference pose and
// `start` its description): a FAIL row per joint outside its range (there, or at qpos0 when
// `ref` moved it inside) and one for contacts deeper than their solimp width
// (plumb::StartIssues), else one PASS row naming the start (audit_structure.cc).
void StartRows(const Model& model, const Data& data, const ReferencePose& ref,
               const std::string& start, std::vector<CheckRow>* out);
// `original` is the model as loaded, `model` after --set.
void InertiaLayer(const Model& original, const Model& model, Data& data,
                  std::vector<CheckRow>* out);
void ActuatorLayer(const Model& original, const Model& model, Data& data,
                   const std::vector<Assignment>& sets, const ReferencePose& ref,
                   const AuditOptions& options, std::vector<Observed>* runs,
                   std::vector<CheckRow>* out);
// Actuators as the actuator layer reads them (audit_actuator.cc). ActuatorCtrl is where
// actuator u's first control sits in ctrl and the nu-row arrays (ctrlrange), ActuatorOutput its
// first force output in the nout-row arrays (gear, length, force): MuJoCo 3.12+ actuators may
// take several controls (a pid takes two), so these are not u.
int ActuatorCtrl(const mjModel* m, int u);
int ActuatorOutput(const mjModel* m, int u);
bool ActuatorCtrlLimited(const mjModel* m, int u);
const mjtNum* ActuatorCtrlRange(const mjModel* m, int u);  // lo, hi
double ActuatorGear(const mjModel* m, int u);              // gear[0] of its first output
// The gear as a row prints it: one number for a joint or tendon, the wrench for a site.
std::string ActuatorGearText(const mjModel* m, int u);
// The force interval [lo, hi] actuator u can produce; infinite where nothing bounds it.
std::pair<double, double> ActuatorForceInterval(const mjModel* m, int u);

// What kind of response a ctrl step gives.
enum class ActuatorKind { kPositionServo, kVelocityServo, kMotor, kOther };
ActuatorKind ActuatorKindOf(const mjModel* m, int u);

// Step responses of up to 12 actuators (audit_step.cc), within one dof-step budget for all,
// from `ref` after `sets`, gravity and contacts off: a position servo's step stays within its
// joint's (tendon's) range, the joints an equality or tendon ties to its joint move with it,
// and a response a limit, an equality, a load or a saturated force decided says so.
void StepResponses(const Model& original, const Model& model, const std::vector<Assignment>& sets,
                   const ReferencePose& ref, const AuditOptions& options,
                   std::vector<Observed>* runs, std::vector<CheckRow>* out);

// The stability margin of every servo (audit_servo.cc); `data` after mj_forward at the
// reference pose.
void ServoStability(const Model& model, const Data& data, std::vector<CheckRow>* out);
// actuator.timescale (audit_timescale.cc): the period and damping time of every servo and of
// every joint and tendon spring against the timestep, judged by how far the integrator's step
// response departs from the exact one; `data` after mj_forward at the reference pose.
void ServoTimescales(const Model& model, const Data& data, std::vector<CheckRow>* out);
// The centre of mass and principal axes of body b against those of its shape (`solids.shape`,
// or the other of its visual and colliding geoms where that shape has open meshes and they are
// closed) filled uniformly (audit_inertia_frame.cc): WARN row inertia.frame when the inertial
// frame looks written in another frame. `com_flagged`: inertia.com already flags
// the body's centre of mass, so only the axes can raise the row. For a body whose mass and
// principal moments are sound (positive, triangle, not a marker).
void InertialFrameAgainstShape(const Model& model, int b, const BodySolids& solids,
                               bool com_flagged, std::vector<CheckRow>* out);
// inertia.density (audit_density.cc) for body b when it is the root of a moving weld group (b
// and the bodies welded to it, which move as one; nothing for a body welded to its parent): a
// WARN row about b when the group's mass in the volume of its bodies' shapes is no solid's
// density, and where the MJCF is at hand a WARN row per geom whose written mass is none in its
// own volume (`geom_masses`: compat::WrittenGeomMasses, `written`: compat::ExplicitInertials;
// null when unknown), unless that geom is the cause the group's row names. `shapes`: BodySolid
// of every moving body, by body id.
void WeldGroupDensity(const Model& model, int b, const std::vector<BodySolids>& shapes,
                      const std::vector<double>* geom_masses, const std::vector<bool>* written,
                      std::vector<CheckRow>* out);
// Mirror pairs (named left/right, FL/FR, ...) that do not mirror (audit_mirror.cc): joints'
// limits and range widths, bodies' masses and principal moments, actuators' gears and gains.
void MirrorJoints(const Model& model, std::vector<CheckRow>* out);
void MirrorBodies(const Model& model, std::vector<CheckRow>* out);
// `data` after mj_forward at the reference pose (the joints' axes and anchors).
void MirrorActuators(const Model& model, const Data& data, std::vector<CheckRow>* out);
// Whether rotor-like actuators on a free body can act independently (audit_rank.cc).
void ActuatorRank(const Model& model, const Data& data, std::vector<CheckRow>* out);
void ContactLayer(const Model& model, const Observed& settle, std::vector<CheckRow>* out);
void BehaviourLayer(const Model& model, const std::vector<Assignment>& sets,
                    const ReferencePose& ref, const Observed& settle, const AuditOptions& options,
                    std::vector<Observed>* runs, std::vector<CheckRow>* out);

}  // namespace plumb::audit

#endif  // PLUMB_SRC_AUDIT_AUDIT_LAYERS_H_
