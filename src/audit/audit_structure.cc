// Audit layer 1, structure: sizes, names, joints (type, axis, range), nq against nv,
// actuators' transmissions and the sensordata layout.

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "audit/audit_layers.h"
#include "core/mujoco_compat.h"
#include "plumb/keyframe.h"
#include "plumb/path.h"

namespace plumb::audit {
namespace {

constexpr const char* L = "structure";

void Counts(const mjModel* m, std::vector<CheckRow>* out) {
  out->push_back(
      Make(L, "structure.counts", "",
           fmt::format("nbody {} njnt {} nq {} nv {} nu {} na {} nsensor {} ngeom {}", m->nbody,
                       m->njnt, m->nq, m->nv, m->nu, m->na, m->nsensor, m->ngeom),
           "", CheckStatus::kPass, "sizes of the compiled model"));
}

// Names matter where people and code refer to elements.
void UnnamedElements(const Model& model, std::vector<CheckRow>* out) {
  const mjModel* m = model.get();
  struct Kind {
    const char* noun;
    const char* plural;
    int obj;
    int count;
  } kinds[] = {{"joint", "joints", mjOBJ_JOINT, static_cast<int>(m->njnt)},
               {"actuator", "actuators", mjOBJ_ACTUATOR, compat::ActuatorCount(m)},
               {"sensor", "sensors", mjOBJ_SENSOR, static_cast<int>(m->nsensor)},
               {"body", "bodies", mjOBJ_BODY, static_cast<int>(m->nbody)}};
  for (const Kind& k : kinds) {
    std::vector<std::string> unnamed, free;
    for (int i = 0; i < k.count; ++i) {
      if (k.obj == mjOBJ_BODY && !Moves(m, i)) continue;
      if (!model.Name(k.obj, i).empty()) continue;
      // a free joint is its body's: qpos[body] and logs name it by the body (a scene's loose
      // object often has an unnamed one), so it is only shown
      bool loose = k.obj == mjOBJ_JOINT && m->jnt_type[i] == mjJNT_FREE;
      (loose ? free : unnamed).push_back("#" + std::to_string(i));
    }
    if (!free.empty()) {
      out->push_back(Make(L, "structure.unnamed_free_joints",
                          fmt::format("joints {}", fmt::join(free, ", ")),
                          fmt::format("{} unnamed", free.size()), "", CheckStatus::kPass,
                          "free joints without a name: their bodies name them"));
    }
    if (unnamed.empty()) continue;
    std::string list = fmt::format(
        "{}",
        fmt::join(unnamed.begin(), unnamed.begin() + std::min<size_t>(8, unnamed.size()), ", "));
    if (unnamed.size() > 8) list += fmt::format(", ... ({} in all)", unnamed.size());
    out->push_back(WithNumbers(
        Make(L, std::string("structure.unnamed_") + k.plural, fmt::format("{} {}", k.plural, list),
             fmt::format("{} unnamed", unnamed.size()), "0", CheckStatus::kWarn,
             fmt::format("name every {}: controllers, logs and plumb paths (qpos[name]) refer "
                         "to {} by name, ids shift when the model changes",
                         k.noun, k.plural)),
        {static_cast<double>(unnamed.size()), ""}, {0, ""}));
  }
}

// A limited joint's range: empty (FAIL), wider than it can turn or slide (WARN), or a hinge
// range so narrow that radians were probably written as degrees (WARN).
void JointRange(const mjModel* m, int j, const CheckElement& element, std::vector<CheckRow>* out) {
  int type = m->jnt_type[j];
  double lo = m->jnt_range[2 * j], hi = m->jnt_range[2 * j + 1];
  bool limited = m->jnt_limited[j];
  std::string range = limited ? fmt::format("[{:.4g}, {:.4g}]", lo, hi) : "unlimited";
  bool rotational = type == mjJNT_HINGE || type == mjJNT_BALL;
  // as numbers: the span hi - lo, which each bound limits
  Quantity span{hi - lo, rotational ? "rad" : "m"};
  if (limited && hi <= lo) {
    out->push_back(WithNumbers(
        Make(L, "structure.joint_range", element, range, "lower < upper", CheckStatus::kFail,
             "a limited joint with an empty range is locked: give range=\"lo hi\" "
             "or drop limited"),
        span, {0, span.unit}));
  } else if (limited && rotational && std::max(-lo, hi) > 4 * M_PI * (1 + 1e-6)) {
    // a bound more than two turns from zero: degrees read as radians (range="-90 90"); ranges
    // of exactly +-2*pi or +-3*pi, as printed with rounding (6.28319), are meant
    out->push_back(WithNumbers(
        Make(L, "structure.joint_range", element, range, "|bound| <= 4*pi rad", CheckStatus::kWarn,
             "a bound more than two turns from zero: was the range written in degrees with "
             "<compiler angle=\"radian\">?"),
        {std::max(-lo, hi), "rad"}, {4 * M_PI, "rad"}));
  } else if (limited && type == mjJNT_SLIDE && hi - lo > 100) {
    out->push_back(
        WithNumbers(Make(L, "structure.joint_range", element, range, "<= 100 m", CheckStatus::kWarn,
                         "a slide range this long never engages: check units"),
                    span, {100.0, span.unit}));
  } else if (limited && type == mjJNT_HINGE && hi - lo < 0.1) {
    // MJCF angles are degrees unless <compiler angle="radian">: radians written there
    // become a range 57 times too narrow
    out->push_back(WithNumbers(
        Make(L, "structure.joint_range", element, range + " rad", ">= 0.1 rad", CheckStatus::kWarn,
             fmt::format("a hinge range of {:.2g} degrees barely moves: MJCF reads angles in "
                         "degrees unless <compiler angle=\"radian\">; were radians written?",
                         (hi - lo) * 180 / M_PI)),
        span, {0.1, "rad"}));
  }
}

// Joints: type, axis, addresses, range; a range warning comes with the joint's row.
void Joints(const Model& model, std::vector<CheckRow>* out) {
  const mjModel* m = model.get();
  for (int j = 0; j < m->njnt; ++j) {
    int type = m->jnt_type[j];
    CheckElement element = ElementOf(model, mjOBJ_JOINT, j, "joint");
    JointRange(m, j, element, out);
    std::string range = m->jnt_limited[j] ? fmt::format("[{:.4g}, {:.4g}]", m->jnt_range[2 * j],
                                                        m->jnt_range[2 * j + 1])
                                          : "unlimited";
    if (j < kMaxListed) {
      const mjtNum* axis = m->jnt_axis + 3 * j;
      out->push_back(Make(L, "structure.joint", element,
                          fmt::format("{} axis ({:.3g} {:.3g} {:.3g}) qpos[{}] dof[{}] range {}",
                                      compat::NameOf(compat::kJointTypes, type), axis[0], axis[1],
                                      axis[2], m->jnt_qposadr[j], m->jnt_dofadr[j], range),
                          "", CheckStatus::kPass,
                          "type, axis (body frame), addresses and range as compiled"));
    }
  }
  ListedNote(L, "structure.joint", "joints", m->njnt, out);
}

// nq against nv: which joints make them differ.
void NqNv(const Model& model, std::vector<CheckRow>* out) {
  const mjModel* m = model.get();
  if (m->nq != m->nv) {
    std::vector<std::string> causes;
    for (int j = 0; j < m->njnt && causes.size() < 8; ++j) {
      if (m->jnt_type[j] == mjJNT_FREE || m->jnt_type[j] == mjJNT_BALL) {
        causes.push_back(Elem(model, mjOBJ_JOINT, j,
                              compat::NameOf(compat::kJointTypes, m->jnt_type[j]).c_str()));
      }
    }
    out->push_back(Make(L, "structure.nq_nv", fmt::format("{}", fmt::join(causes, ", ")),
                        fmt::format("nq {} != nv {}", m->nq, m->nv), "", CheckStatus::kPass,
                        "free joints have 7 qpos and 6 dofs, ball joints 4 and 3: index qvel, "
                        "qacc and forces with dof addresses, never qpos addresses"));
  }
}

// Actuators -> transmission targets, sensors -> sensordata layout.
void ActuatorsAndSensors(const Model& model, std::vector<CheckRow>* out) {
  const mjModel* m = model.get();
  for (int u = 0; u < compat::ActuatorCount(m) && u < kMaxListed; ++u) {
    int trn = m->actuator_trntype[u];
    int target_type = trn == mjTRN_TENDON ? mjOBJ_TENDON
                      : trn == mjTRN_SITE ? mjOBJ_SITE
                      : trn == mjTRN_BODY ? mjOBJ_BODY
                                          : mjOBJ_JOINT;
    out->push_back(Make(L, "structure.actuator", ElementOf(model, mjOBJ_ACTUATOR, u, "actuator"),
                        fmt::format("{} -> {}", compat::NameOf(compat::kTransmissions, trn),
                                    Elem(model, target_type, m->actuator_trnid[2 * u],
                                         compat::NameOf(compat::kTransmissions, trn).c_str())),
                        "", CheckStatus::kPass, "transmission and the element it drives"));
  }
  ListedNote(L, "structure.actuator", "actuators", compat::ActuatorCount(m), out);
  for (int s = 0; s < m->nsensor && s < kMaxListed; ++s) {
    out->push_back(Make(L, "structure.sensor", ElementOf(model, mjOBJ_SENSOR, s, "sensor"),
                        fmt::format("{} sensordata[{}..{}]",
                                    compat::NameOf(compat::kSensorTypes, m->sensor_type[s]),
                                    m->sensor_adr[s], m->sensor_adr[s] + m->sensor_dim[s] - 1),
                        "", CheckStatus::kPass, "sensor type and its place in sensordata"));
  }
  ListedNote(L, "structure.sensor", "sensors", m->nsensor, out);
}

// MuJoCo's compiler takes "nan" and "inf" in most attributes with at most a warning.
void FiniteParameters(const Model& model, std::vector<CheckRow>* out) {
  NonFiniteValues bad = NonFiniteParameters(model);
  if (bad.total == 0) {
    out->push_back(Make(L, "structure.finite", "", "all finite", "finite", CheckStatus::kPass,
                        "every floating-point parameter of the compiled model is finite"));
    return;
  }
  out->push_back(WithNumbers(
      Make(L, "structure.finite",
           fmt::format("{}{}", fmt::join(bad.first, ", "),
                       bad.total > static_cast<long>(bad.first.size()) ? ", ..." : ""),
           fmt::format("{} NaN or infinite", bad.total), "finite", CheckStatus::kFail,
           "give a finite value to the MJCF attribute that sets each one: MuJoCo compiles NaN and "
           "infinity without an error, and such a value poisons the steps that use it"),
      {static_cast<double>(bad.total), ""}));
}

// What to do about a start its authors would not have meant (`start`: DescribeStart's words),
// to make it `right` ("inside the ranges", "with no geoms inside each other").
std::string FixTheStart(const std::string& start, const std::string& right) {
  if (start.rfind("qpos0", 0) == 0) {
    return "add a keyframe 'home' " + right + " (MJCF <keyframe><key name=\"home\" "
           "qpos=\"...\"/>), which plumb starts from, or move qpos0 with the joints' ref";
  }
  return "correct the start (" + start + ") so that it lies " + right;
}

// The FAIL row of joint `issue` outside its range at the start; `moved_to` is where the
// reference pose brought it instead (NaN: nowhere, the run starts there).
CheckRow OutsideRow(const Model& model, const StartIssue& issue, const std::string& start,
                    double moved_to) {
  std::string where = FixTheStart(start, "inside the ranges");
  std::string fix =
      std::isnan(moved_to)
          ? "the joint limit throws it back in the first steps, and every run from this start "
            "measures that instead of the robot: " + where
          : fmt::format("the model has no keyframe, and from qpos0 its limit would throw the "
                        "joint back in the first steps: the audit's runs start it at {:.4g} {}, "
                        "1% inside its range: {}",
                        moved_to, issue.unit, where);
  double bound = issue.value < issue.lo ? issue.lo : issue.hi;
  return WithNumbers(
      Make(L, "structure.start", ElementOf(model, mjOBJ_JOINT, issue.id, "joint"),
           fmt::format("{} puts it at {:.4g} {}, outside its range",
                       std::isnan(moved_to) ? "the start (" + start + ")" : std::string("qpos0"),
                       issue.value, issue.unit),
           fmt::format("within [{:.4g}, {:.4g}] {}", issue.lo, issue.hi, issue.unit),
           CheckStatus::kFail, fix),
      {issue.value, issue.unit}, {bound, issue.unit});
}

}  // namespace

void StartRows(const Model& model, const Data& data, const ReferencePose& ref,
               const std::string& start, std::vector<CheckRow>* out) {
  std::vector<StartIssue> issues = StartIssues(model, data);
  int joints = 0;
  // the joints qpos0 puts outside their ranges, which the reference pose moved inside
  for (const StartIssue& issue : MovedIntoRange(model, data, ref)) {
    double moved_to = data->qpos[model->jnt_qposadr[issue.id]];
    if (joints++ < kMaxListed) out->push_back(OutsideRow(model, issue, start, moved_to));
  }
  for (const StartIssue& issue : issues) {
    if (issue.kind != StartIssue::Kind::kJointOutsideRange) continue;
    if (joints++ < kMaxListed) out->push_back(OutsideRow(model, issue, start, NAN));
  }
  ListedNote(L, "structure.start", "joints outside their range", joints, out);
  std::vector<StartIssue> deep;
  for (const StartIssue& issue : issues) {
    if (issue.kind == StartIssue::Kind::kDeepContact) deep.push_back(issue);
  }
  if (!deep.empty()) {
    int contacts = static_cast<int>(deep.size());
    const StartIssue& deepest = deep.front();
    out->push_back(WithNumbers(
        Make(L, "structure.start_contact", DescribeStartIssues(deep, 4),
             fmt::format("{} contact{} deeper than the pair's solimp width at the start ({}); "
                         "deepest {:.3g} mm",
                         contacts, contacts == 1 ? "" : "s", start, 1e3 * deepest.value),
             fmt::format("<= solimp width ({:.3g} mm)", 1e3 * deepest.hi), CheckStatus::kFail,
             "MuJoCo pushes interpenetrating geoms apart at full stiffness in the first steps, "
             "and every run from this start measures that (fingers closed on each other, feet "
             "below the floor): " + FixTheStart(start, "with no geoms inside each other")),
        {deepest.value, "m"}, {deepest.hi, "m"}));
  }
  if (issues.empty() && joints == 0) {
    out->push_back(Make(L, "structure.start", "", start, "", CheckStatus::kPass,
                        "the start every check is judged from: every limited joint within its "
                        "range, no contact deeper than its solimp width"));
  }
}

void StructureLayer(const Model& model, std::vector<CheckRow>* out) {
  Counts(model.get(), out);
  FiniteParameters(model, out);
  UnnamedElements(model, out);
  Joints(model, out);
  MirrorJoints(model, out);
  NqNv(model, out);
  ActuatorsAndSensors(model, out);
  DelayRows(model, "sensor", L, "structure.sensor_delay", out);
  SolrefClamps(model, out);
}

}  // namespace plumb::audit
