// plumb snapshot: what a regression should notice, written as stable JSON: sizes, options,
// every recorded field of every named element, and a golden trajectory.

#include "plumb/regression.h"

#include <cmath>
#include <map>

#include "core/fields.h"
#include "core/joint_size.h"
#include "core/mujoco_compat.h"
#include "plumb/error.h"
#include "plumb/keyframe.h"
#include "plumb/run.h"
#include "plumb/version.h"
#include "regression/regression_internal.h"

namespace plumb {
using internal::FieldInfo;
using internal::Fields;
using internal::FieldSource;
using internal::JointDofSize;
using internal::SnapshotElementName;
using internal::SnapshotJson;
using nlohmann::ordered_json;

namespace {

// The element kinds a snapshot records, keyed by name, and the mjModel size counting them.
struct Section {
  const char* name;  // "body"
  const char* size;  // "nbody"
  int obj;           // names come from this object type
};
constexpr Section kSections[] = {
    {"body", "nbody", mjOBJ_BODY},       {"joint", "njnt", mjOBJ_JOINT},
    {"dof", "nv", mjOBJ_JOINT},          {"geom", "ngeom", mjOBJ_GEOM},
    {"site", "nsite", mjOBJ_SITE},       {"actuator", "nu", mjOBJ_ACTUATOR},
    {"sensor", "nsensor", mjOBJ_SENSOR}, {"tendon", "ntendon", mjOBJ_TENDON},
    {"equality", "neq", mjOBJ_EQUALITY}, {"keyframe", "nkey", mjOBJ_KEY},
};

// Fields that are not part of what a regression should notice: derived constants (they
// follow the fields they come from), appearance, and internal bookkeeping that shifts
// whenever anything is added.
bool Recorded(const std::string& f) {
  static const char* kSkip[] = {
      "body_subtreemass", "body_invweight0",   "dof_invweight0", "dof_M0",
      "tendon_length0",   "tendon_invweight0", "actuator_acc0",  "actuator_length0",
      "geom_rbound",      "body_rootid",       "body_weldid",    "body_sameframe",
      "body_simple",      "geom_sameframe",    "site_sameframe", "dof_parentid",
      "dof_Madr",         "dof_simplenum",     "body_mocapid",   "geom_dataid",
      "geom_matid",       "site_matid",        "tendon_matid",   "dof_jntid",
      "dof_bodyid"};
  for (const char* s : kSkip) {
    if (f == s) return false;
  }
  auto ends = [&](const char* suffix) {
    std::string s(suffix);
    return f.size() > s.size() && f.compare(f.size() - s.size(), s.size(), s) == 0;
  };
  if (ends("_rgba") || f.rfind("name_", 0) == 0) return false;
  if ((ends("adr") || ends("num")) && f != "jnt_qposadr" && f != "jnt_dofadr" &&
      f != "sensor_adr") {
    return false;
  }
  return true;
}

// Object type an id field refers to, so ids are stored as names (stable when elements
// are added before them); -1 when the field is not an id.
int IdTarget(const std::string& f, const mjModel* m, int row) {
  if (f == "body_parentid" || f == "jnt_bodyid" || f == "geom_bodyid" || f == "site_bodyid") {
    return mjOBJ_BODY;
  }
  if (f == "actuator_trnid") {
    int t = m->actuator_trntype[row];
    return t == mjTRN_TENDON ? mjOBJ_TENDON
           : t == mjTRN_SITE ? mjOBJ_SITE
           : t == mjTRN_BODY ? mjOBJ_BODY
                             : mjOBJ_JOINT;
  }
  if (f == "sensor_objid") return m->sensor_objtype[row];
  if (f == "sensor_refid") return m->sensor_reftype[row];
  return -1;
}

// Key of row `row` of a section: the element's name, "#id" when unnamed; dofs are
// named after their joint ("root[3]" for the 4th dof of a free joint).
std::string RowKey(const Model& model, const Section& section, int row) {
  const mjModel* m = model.get();
  if (std::string(section.name) == "dof") {
    int j = m->dof_jntid[row];
    std::string joint = SnapshotElementName(model, mjOBJ_JOINT, j);
    int n = JointDofSize(m->jnt_type[j]);
    return n == 1 ? joint : joint + "[" + std::to_string(row - m->jnt_dofadr[j]) + "]";
  }
  return SnapshotElementName(model, section.obj, row);
}

ordered_json Value(const Model& model, const Data& data, const Path& p) {
  const FieldInfo& f = Fields()[p.field_index];
  if (f.type == compat::ElemType::kNum || f.type == compat::ElemType::kFloat) {
    if (p.count == 1) return ReadValue(model, data, p);
    ordered_json a = ordered_json::array();
    for (long k = 0; k < p.count; ++k) a.push_back(ReadValue(model, data, p, k));
    return a;
  }
  if (p.count == 1) return static_cast<long long>(ReadValue(model, data, p));
  ordered_json a = ordered_json::array();
  for (long k = 0; k < p.count; ++k)
    a.push_back(static_cast<long long>(ReadValue(model, data, p, k)));
  return a;
}

ordered_json Structure(const Model& model, const Data& data) {
  const mjModel* m = model.get();
  ordered_json out;
  for (const Section& section : kSections) {
    // actuators: one row per actuator, its arrays counted by nu on 2.x and by nactuator,
    // nu (controls) or nout (force outputs) on 3.x, each read by the actuator's id
    bool actuators = section.obj == mjOBJ_ACTUATOR;
    auto in_section = [&](const FieldInfo& f) {
      if (!actuators) return f.row_kind == section.size;
      return f.row_kind == "nu" || f.row_kind == "nactuator" || f.row_kind == "nout";
    };
    long rows = actuators ? compat::ActuatorCount(m) : 0;
    for (const FieldInfo& f : Fields()) {
      if (!actuators && f.source == FieldSource::kModelSize && f.name == section.size) {
        rows = static_cast<long>(ReadValue(model, data, ResolvePath(model, f.name)));
      }
    }
    ordered_json elements = ordered_json::object();
    for (int row = 0; row < rows; ++row) {
      ordered_json e = ordered_json::object();
      e["id"] = row;
      for (const FieldInfo& f : Fields()) {
        if (f.source != FieldSource::kModelArray || !in_section(f)) continue;
        if (f.type == compat::ElemType::kOther || f.type == compat::ElemType::kChar) continue;
        if (!Recorded(f.name) || f.cols(m) == 0) continue;
        Path p = ResolvePath(model, f.name + (actuators ? "[#" : "[") + std::to_string(row) + "]");
        int target = IdTarget(f.name, m, row);
        if (target >= 0) {
          ordered_json ids = ordered_json::array();
          for (long k = 0; k < p.count; ++k) {
            ids.push_back(
                SnapshotElementName(model, target, static_cast<int>(ReadValue(model, data, p, k))));
          }
          e[f.name] = p.count == 1 ? ids[0] : ids;
        } else if (p.count == 1 &&
                   compat::EnumFieldName(f.name, static_cast<int>(ReadValue(model, data, p)))) {
          // enumerations by their MJCF names: MuJoCo renumbers some between releases
          e[f.name] = *compat::EnumFieldName(f.name, static_cast<int>(ReadValue(model, data, p)));
        } else {
          e[f.name] = Value(model, data, p);
        }
      }
      elements[RowKey(model, section, row)] = e;
    }
    out[section.name] = elements;
  }
  return out;
}

ordered_json Options(const Model& model, const Data& data) {
  ordered_json out = ordered_json::object();
  for (const FieldInfo& f : Fields()) {
    if (f.source != FieldSource::kOption) continue;
    out[f.name] = Value(model, data, ResolvePath(model, f.name));
  }
  // enumerations by their MJCF names, so a diff reads "opt.cone: pyramidal → elliptic"
  out["opt.integrator"] = compat::NameOf(compat::kIntegrators, model->opt.integrator);
  out["opt.cone"] = compat::NameOf(compat::kCones, model->opt.cone);
  out["opt.solver"] = compat::NameOf(compat::kSolvers, model->opt.solver);
  out["opt.jacobian"] = compat::NameOf(compat::kJacobians, model->opt.jacobian);
  return out;
}

// The golden trajectory: qpos, qvel, act after each of kSnapshotSteps steps.
ordered_json Trajectory(const Model& model, const std::vector<Assignment>& sets,
                        std::string* diverged) {
  Model work = model.Clone();
  Data data(work);
  // the reference pose every command shares: keyframe home, else test, else qpos0
  ReferencePose pose = FindReferencePose(work);
  StartAtPose(work, data, pose, sets);
  const mjModel* m = work.get();
  ordered_json qpos = ordered_json::array(), qvel = qpos, act = qpos;
  RunSpec spec;
  spec.until = kSnapshotSteps * m->opt.timestep;
  spec.every = m->opt.timestep;
  spec.before_step = [m](mjData* d, long) {
    for (int i = 0; i < m->nu; ++i) {
      if (!m->actuator_ctrllimited[i]) {
        d->ctrl[i] = 0;
        continue;
      }
      double lo = m->actuator_ctrlrange[2 * i], hi = m->actuator_ctrlrange[2 * i + 1];
      d->ctrl[i] =
          0.5 * (lo + hi) + 0.25 * (hi - lo) * std::sin(2 * M_PI * d->time * (1 + 0.37 * i));
    }
  };
  spec.after_step = [&](const mjData* d, long) {
    qpos.push_back(std::vector<double>(d->qpos, d->qpos + m->nq));
    qvel.push_back(std::vector<double>(d->qvel, d->qvel + m->nv));
    act.push_back(std::vector<double>(d->act, d->act + m->na));
  };
  NullSink sink;
  RunResult r = Run(work, data, spec, sink);
  TakeMujocoWarnings();
  if (r.diverged) *diverged = r.divergence->reason;
  return {
      {"steps", kSnapshotSteps},
      {"start", pose.keyframe >= 0 ? "keyframe " + work.Name(mjOBJ_KEY, pose.keyframe) : "qpos0"},
      {"controls",
       "ctrl = centre + 0.5*radius*sin(2*pi*t*(1 + 0.37*i)) for ctrl-limited "
       "actuators, 0 otherwise"},
      {"qpos", qpos},
      {"qvel", qvel},
      {"act", act}};
}

}  // namespace

ordered_json internal::SnapshotJson(const Model& model, const std::vector<Assignment>& sets,
                                    std::string* diverged) {
  Model nominal = model.Clone();
  Data data(nominal);
  ApplyAssignments(nominal, data, sets);
  const mjModel* m = nominal.get();
  ordered_json j;
  j["plumb_snapshot"] = kSnapshotFormat;
  j["plumb_version"] = PLUMB_VERSION;
  j["mujoco_version"] = MujocoVersion();
  j["model"] = std::string(m->names);
  ordered_json texts = ordered_json::array();
  for (const Assignment& a : sets) texts.push_back(a.text);
  j["sets"] = texts;
  ordered_json sizes;
  for (const char* size : {"nq", "nv", "nu", "na", "nbody", "njnt", "ngeom", "nsite", "nsensor",
                           "nsensordata", "ntendon", "neq", "nmocap", "nkey"}) {
    sizes[size] = static_cast<long long>(ReadValue(nominal, data, ResolvePath(nominal, size)));
  }
  j["sizes"] = sizes;
  j["options"] = Options(nominal, data);
  j["structure"] = Structure(nominal, data);
  j["trajectory"] = Trajectory(model, sets, diverged);
  return j;
}

std::string internal::SnapshotElementName(const Model& model, int obj, int id) {
  if (id < 0) return "(none)";
  std::string name = model.Name(obj, id);
  if (obj == mjOBJ_BODY && id == 0) return "world";
  return name.empty() ? "#" + std::to_string(id) : name;
}

std::string MakeSnapshot(const Model& model, const std::vector<Assignment>& sets,
                         std::string* divergence) {
  std::string diverged;
  std::string text = SnapshotJson(model, sets, &diverged).dump(2) + "\n";
  if (divergence) *divergence = diverged;
  return text;
}

}  // namespace plumb
