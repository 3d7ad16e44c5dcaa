#include "plumb/regression.h"

#include <cmath>
#include <map>
#include <nlohmann/json.hpp>

#include "core/fields.h"
#include "core/mujoco_compat.h"
#include "plumb/version.h"
#include "plumb/error.h"
#include "plumb/keyframe.h"
#include "plumb/run.h"

#include <set>

namespace plumb {

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
    {"equality", "neq", mjOBJ_EQUALITY},
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

std::string NameOr(const Model& model, int obj, int id) {
  if (id < 0) return "(none)";
  std::string name = model.Name(obj, id);
  if (obj == mjOBJ_BODY && id == 0) return "world";
  return name.empty() ? "#" + std::to_string(id) : name;
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
    std::string joint = NameOr(model, mjOBJ_JOINT, j);
    int n = m->jnt_type[j] == mjJNT_FREE ? 6 : m->jnt_type[j] == mjJNT_BALL ? 3 : 1;
    return n == 1 ? joint : joint + "[" + std::to_string(row - m->jnt_dofadr[j]) + "]";
  }
  return NameOr(model, section.obj, row);
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
            ids.push_back(NameOr(model, target, static_cast<int>(ReadValue(model, data, p, k))));
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
  return {{"steps", kSnapshotSteps},
          {"start", pose.keyframe >= 0 ? "keyframe " + work.Name(mjOBJ_KEY, pose.keyframe) : "qpos0"},
          {"controls",
           "ctrl = centre + 0.5*radius*sin(2*pi*t*(1 + 0.37*i)) for ctrl-limited "
           "actuators, 0 otherwise"},
          {"qpos", qpos},
          {"qvel", qvel},
          {"act", act}};
}

ordered_json Snapshot(const Model& model, const std::vector<Assignment>& sets,
                      std::string* diverged) {
  Model nominal = model.Clone();
  Data data(nominal);
  ApplyAssignments(nominal, data, sets);
  const mjModel* m = nominal.get();
  ordered_json j;
  j["plumb_snapshot"] = 1;
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

// Parameters differ when |a - b| > tol * max(|a|, |b|): relative, so a damping of 1e-8
// that becomes 2e-8 is a change.
bool CloseRelative(double a, double b, double tol) {
  if (std::isnan(a) || std::isnan(b)) return std::isnan(a) && std::isnan(b);
  return std::fabs(a - b) <= tol * std::max(std::fabs(a), std::fabs(b));
}

// Trajectory values differ when |a - b| > tol * max(1, |a|, |b|): an angle passing
// through zero has no meaningful relative error.
bool CloseTrajectory(double a, double b, double tol) {
  return std::fabs(a - b) <= tol * std::max({1.0, std::fabs(a), std::fabs(b)});
}

std::string Show(const ordered_json& v) {
  if (v.is_number_float()) {
    char buffer[32];
    std::snprintf(buffer, sizeof(buffer), "%.10g", v.get<double>());
    return buffer;
  }
  if (v.is_string()) return v.get<std::string>();
  if (v.is_array()) {
    std::string out = "[";
    for (std::size_t i = 0; i < v.size(); ++i) out += (i ? " " : "") + Show(v[i]);
    return out + "]";
  }
  return v.dump();
}

bool Same(const ordered_json& a, const ordered_json& b, double tol) {
  if (a.is_number() && b.is_number()) {
    return CloseRelative(a.get<double>(), b.get<double>(), tol);
  }
  if (a.is_array() && b.is_array()) {
    if (a.size() != b.size()) return false;
    for (std::size_t i = 0; i < a.size(); ++i) {
      if (!Same(a[i], b[i], tol)) return false;
    }
    return true;
  }
  return a == b;
}

// ---- the shape of a snapshot read back ------------------------------------------------

// What a value must look like, in words: "a number", "an array of 3 numbers".
std::string Shape(const ordered_json& v) {
  if (v.is_number()) return "a number";
  if (v.is_string()) return "a string";
  if (v.is_array()) {
    std::string of = v.empty() ? "values" : v[0].is_string() ? "strings" : "numbers";
    return "an array of " + std::to_string(v.size()) + " " + of;
  }
  if (v.is_object()) return "an object";
  return "null";
}

[[noreturn]] void Damaged(const std::string& entry, const std::string& expected,
                          const ordered_json& got) {
  std::string shown = got.dump();
  if (shown.size() > 40) shown = shown.substr(0, 37) + "...";
  throw ValueError(entry + ": expected " + expected + ", got " + shown);
}

const ordered_json& Member(const ordered_json& parent, const std::string& where,
                           const std::string& key, bool (ordered_json::*is)() const noexcept,
                           const char* expected) {
  auto at = parent.find(key);
  if (at == parent.end()) throw ValueError(where + key + ": missing");
  if (!((*at).*is)()) Damaged(where + key, expected, *at);
  return *at;
}

// A scalar or an array of scalars, as the structure and options sections hold; of the
// same shape as the current model's value when there is one (only the *_user arrays
// change width with the model).
void ExpectFieldValue(const ordered_json& v, const std::string& entry,
                      const ordered_json* current) {
  bool user = entry.size() > 5 && entry.compare(entry.size() - 5, 5, "_user") == 0;
  if (current && Shape(*current) != Shape(v) && !(user && v.is_array())) {
    Damaged(entry, Shape(*current), v);
  }
  auto scalar = [](const ordered_json& x) { return x.is_number() || x.is_string(); };
  if (scalar(v)) return;
  if (!v.is_array()) Damaged(entry, "a number, a string or an array of them", v);
  for (std::size_t i = 0; i < v.size(); ++i) {
    if (!scalar(v[i])) {
      Damaged(entry + "[" + std::to_string(i) + "]", "a number or a string", v[i]);
    }
  }
}

// Snapshots written before enumerations were recorded by name hold their numbers. Under
// the MuJoCo that wrote them the numbers are named as a new snapshot would name them;
// under another, whose numbering may differ (mjtSensor's did), they stay marked with
// the version that numbered them, so a diff shows them instead of guessing.
void NameNumberedEnums(ordered_json* snapshot) {
  if (!snapshot->is_object() || !snapshot->contains("structure") ||
      !(*snapshot)["structure"].is_object()) {
    return;
  }
  auto version = snapshot->find("mujoco_version");
  std::string writer = version != snapshot->end() && version->is_string()
                           ? version->get<std::string>()
                           : "an unknown version";
  bool same = writer == MujocoVersion();
  for (auto& [section, elements] : (*snapshot)["structure"].items()) {
    if (!elements.is_object()) continue;
    for (auto& [name, fields] : elements.items()) {
      if (!fields.is_object()) continue;
      for (auto& [field, value] : fields.items()) {
        if (!value.is_number_integer()) continue;
        int number = value.get<int>();
        std::optional<std::string> named = compat::EnumFieldName(field, number);
        if (!named) continue;
        value = same ? *named
                     : "type " + std::to_string(number) + " as numbered by MuJoCo " + writer;
      }
    }
  }
}

// Checks that `before` has every entry DiffSnapshot reads, with the right types and
// lengths (`after` is the current model's snapshot, for the shapes of fields).
// @throws ValueError naming the entry, e.g. "structure.body.link.body_mass: expected a
// number, got "heavy"".
void ValidateSnapshot(const ordered_json& before, const ordered_json& after) {
  using J = ordered_json;
  if (!before.is_object()) Damaged("the top level", "an object", before);
  const J& version = Member(before, "", "plumb_snapshot", &J::is_number_integer, "an integer");
  if (version != 1) {
    throw ValueError("plumb_snapshot: version " + version.dump() +
                     " is not one this plumb reads (1)");
  }
  Member(before, "", "mujoco_version", &J::is_string, "a string");
  if (before.contains("sets")) {  // snapshots before the --set values were recorded lack it
    const J& sets = Member(before, "", "sets", &J::is_array, "an array of --set values");
    for (std::size_t i = 0; i < sets.size(); ++i) {
      if (!sets[i].is_string()) Damaged("sets[" + std::to_string(i) + "]", "a string", sets[i]);
    }
  }
  const J& sizes = Member(before, "", "sizes", &J::is_object, "an object");
  for (const auto& [key, value] : sizes.items()) {
    if (!value.is_number_integer() || value.get<long long>() < 0) {
      Damaged("sizes." + key, "a count (an integer >= 0)", value);
    }
  }
  const J& options = Member(before, "", "options", &J::is_object, "an object");
  for (const auto& [key, value] : options.items()) {
    auto now = after["options"].find(key);
    ExpectFieldValue(value, "options." + key, now == after["options"].end() ? nullptr : &*now);
  }
  const J& structure = Member(before, "", "structure", &J::is_object, "an object");
  for (const auto& [section, elements] : structure.items()) {
    std::string where = "structure." + section;
    if (!elements.is_object()) Damaged(where, "an object of elements", elements);
    const J* current =
        after["structure"].contains(section) ? &after["structure"][section] : nullptr;
    for (const auto& [name, fields] : elements.items()) {
      std::string element = where + "." + name;
      if (!fields.is_object()) Damaged(element, "an object of fields", fields);
      const J* now = current && current->contains(name) ? &(*current)[name] : nullptr;
      for (const auto& [field, value] : fields.items()) {
        const J* now_value = now && now->contains(field) ? &(*now)[field] : nullptr;
        ExpectFieldValue(value, element + "." + field, now_value);
      }
    }
  }
  const J& trajectory = Member(before, "", "trajectory", &J::is_object, "an object");
  for (const char* field : {"qpos", "qvel", "act"}) {
    const char* size = field[1] == 'p' ? "nq" : field[1] == 'v' ? "nv" : "na";
    const J& rows = Member(trajectory, "trajectory.", field, &J::is_array, "an array of steps");
    const J& n = Member(sizes, "sizes.", size, &J::is_number_integer, "an integer");
    for (std::size_t s = 0; s < rows.size(); ++s) {
      std::string entry = std::string("trajectory.") + field + "[" + std::to_string(s) + "]";
      std::string expected = n.dump() + " numbers (sizes." + size + ")";
      if (!rows[s].is_array() || rows[s].size() != n.get<std::size_t>()) {
        Damaged(entry, "an array of " + expected, rows[s]);
      }
      for (std::size_t i = 0; i < rows[s].size(); ++i) {
        if (!rows[s][i].is_number()) {
          Damaged(entry + "[" + std::to_string(i) + "]", "a number", rows[s][i]);
        }
      }
    }
  }
  if (trajectory["qvel"].size() != trajectory["qpos"].size() ||
      trajectory["act"].size() != trajectory["qpos"].size()) {
    throw ValueError("trajectory: qpos, qvel and act hold different numbers of steps (" +
                     std::to_string(trajectory["qpos"].size()) + ", " +
                     std::to_string(trajectory["qvel"].size()) + ", " +
                     std::to_string(trajectory["act"].size()) + ")");
  }
}

// "qpos[7] (joint 'root')", "act[0] (actuator 'muscle')": which element index `i` of a
// state array belongs to.
std::string StateElement(const Model& model, const std::string& array, std::size_t i) {
  const mjModel* m = model.get();
  std::string label = array + "[" + std::to_string(i) + "]";
  int n = static_cast<int>(i);
  if (array == "qpos") {
    for (int j = m->njnt - 1; j >= 0; --j) {
      if (m->jnt_qposadr[j] <= n) return label + " (joint '" + NameOr(model, mjOBJ_JOINT, j) + "')";
    }
  } else if (array == "qvel" && n < m->nv) {
    return label + " (joint '" + NameOr(model, mjOBJ_JOINT, m->dof_jntid[n]) + "')";
  } else if (array == "act" && n < m->na) {
    for (int u = m->nu - 1; u >= 0; --u) {
      int adr = compat::ActuatorActAddress(m, u);
      if (adr >= 0 && adr <= n) {
        return label + " (actuator '" + NameOr(model, mjOBJ_ACTUATOR, u) + "')";
      }
    }
  }
  return label;
}

}  // namespace

std::string MakeSnapshot(const Model& model, const std::vector<Assignment>& sets,
                         std::string* divergence) {
  std::string diverged;
  std::string text = Snapshot(model, sets, &diverged).dump(2) + "\n";
  if (divergence) *divergence = diverged;
  return text;
}

SnapshotDiff DiffSnapshot(const std::string& text, const Model& model,
                          const std::vector<Assignment>& sets, double tol) {
  ordered_json parsed;
  try {
    parsed = ordered_json::parse(text);
  } catch (const std::exception& e) {
    throw ValueError(std::string("not a plumb snapshot (invalid JSON: ") + e.what() + ")");
  }
  if (!parsed.is_object() || !parsed.contains("plumb_snapshot")) {
    throw ValueError("not a plumb snapshot (no plumb_snapshot entry)");
  }
  SnapshotDiff diff;
  auto change = [&](const char* kind, std::string path, const ordered_json& was,
                    const ordered_json& is, std::string what) {
    SnapshotChange c;
    c.what = std::move(what);
    c.kind = kind;
    c.path = std::move(path);
    c.old_value = was.dump();
    c.new_value = is.dump();
    diff.changes.push_back(std::move(c));
  };
  // the snapshot's own --set values first, then the caller's (which win)
  std::vector<Assignment> all;
  std::vector<std::pair<std::string, std::string>> refused;  // text, reason
  if (parsed.contains("sets") && parsed["sets"].is_array()) {
    for (const ordered_json& text : parsed["sets"]) {
      if (!text.is_string()) continue;  // ValidateSnapshot names it below
      try {
        all.push_back(ParseAssignment(model, text.get<std::string>()));
        diff.sets.push_back(text.get<std::string>());
      } catch (const Error& e) {
        refused.emplace_back(text.get<std::string>(), e.what());
      }
    }
  }
  all.insert(all.end(), sets.begin(), sets.end());
  std::string diverged;
  const ordered_json after = Snapshot(model, all, &diverged);
  NameNumberedEnums(&parsed);
  const ordered_json& before = parsed;  // const: a missing key can never be inserted
  ValidateSnapshot(before, after);
  diff.diverged = !diverged.empty();
  diff.snapshot_mujoco_version = before["mujoco_version"].get<std::string>();
  if (before.contains("plumb_version") && before["plumb_version"].is_string()) {
    diff.snapshot_plumb_version = before["plumb_version"].get<std::string>();
  }
  for (const auto& [text, reason] : refused) {
    change("set", text, text, nullptr,
           "the snapshot's --set '" + text + "' does not apply to the current model (" + reason +
               "); compared without it");
  }
  if (!diff.sets.empty()) {
    std::string list;
    for (const std::string& t : diff.sets)
      list += (list.empty() ? "--set '" : " --set '") + t + "'";
    diff.notes.push_back("the model is simulated with the snapshot's " + list);
  }
  if (before["mujoco_version"] != after["mujoco_version"]) {
    diff.notes.push_back("the snapshot was written with MuJoCo " +
                         before["mujoco_version"].get<std::string>() + ", this is " +
                         after["mujoco_version"].get<std::string>() +
                         ": trajectories differ in the last bits across versions");
  }
  const bool other_version = before["mujoco_version"] != after["mujoco_version"];
  // what MuJoCo's compiler derives from a mesh geom's vertices (its fitted primitive's size,
  // frame and bounding box; and from them each dof's length scale): releases fit them
  // differently from the same mesh file
  static const std::set<std::string> kMeshDerived = {"geom_size", "geom_aabb", "geom_pos",
                                                     "geom_quat", "geom_rbound"};
  const ordered_json none;
  for (const auto& [key, value] : after["sizes"].items()) {
    auto old = before["sizes"].find(key);
    const ordered_json& was = old == before["sizes"].end() ? none : *old;
    if (was != value)
      change("structure", key, was, value, key + ": " + Show(was) + " → " + Show(value));
  }
  for (const auto& [key, value] : after["options"].items()) {
    auto old = before["options"].find(key);
    if (old == before["options"].end()) continue;
    if (!Same(*old, value, tol)) {
      change("option", key, *old, value, key + ": " + Show(*old) + " → " + Show(value));
    }
  }
  for (const auto& [section, elements] : after["structure"].items()) {
    auto found = before["structure"].find(section);
    const ordered_json empty = ordered_json::object();
    const ordered_json& old = found == before["structure"].end() ? empty : *found;
    for (const auto& [name, fields] : old.items()) {
      if (!elements.contains(name)) {
        change("removed", section + "[" + name + "]", fields["id"], nullptr,
               section + " removed: " + name);
      }
    }
    int renumbered = 0;
    std::string first_renumbered;
    ordered_json first_was, first_is;
    for (const auto& [name, fields] : elements.items()) {
      if (!old.contains(name)) {
        change("added", section + "[" + name + "]", nullptr, fields["id"],
               section + " added: " + name + " (id " + Show(fields["id"]) + ")");
        continue;
      }
      const ordered_json& was = old[name];
      for (const auto& [field, value] : fields.items()) {
        if (!was.contains(field)) continue;
        if (field == "id") {
          if (was[field] != value && renumbered++ == 0) {
            first_renumbered = name + ": " + Show(was[field]) + " → " + Show(value);
            first_was = was[field];
            first_is = value;
          }
          continue;
        }
        if (!Same(was[field], value, tol)) {
          // what an element is and where it hangs is structure; its numbers are parameters
          bool structural = value.is_string() ||
                            (field.size() > 5 && field.compare(field.size() - 5, 5, "_type") == 0);
          std::string path = field + "[" + name + "]";
          std::string what = path + ": " + Show(was[field]) + " → " + Show(value);
          bool mesh_derived = section == "geom" && fields.value("geom_type", "") == "mesh" &&
                              kMeshDerived.count(field);
          // a dof's length scale comes from the size of the bodies it moves
          bool size_derived = section == "dof" && field == "dof_length";
          if (other_version && (mesh_derived || size_derived)) {
            // the same mesh, fitted by another release's compiler: not the user's change
            change("compiler", path, was[field], value, what);
            diff.compiler.push_back(diff.changes.back());
            diff.changes.pop_back();
            continue;
          }
          change(structural ? "structure" : "parameter", path, was[field], value, what);
        }
      }
    }
    if (renumbered > 0) {
      change("structure", std::string(section) + " ids", first_was, first_is,
             section + " ids shift: " + std::to_string(renumbered) + " renumbered (first " +
                 first_renumbered + "); code that indexes " + section + "s by id must follow");
    }
  }
  // the golden trajectory, step by step
  const ordered_json& t0 = before["trajectory"];
  const ordered_json& t1 = after["trajectory"];
  if (t0["qpos"].size() != t1["qpos"].size() && !diff.diverged) {
    change("trajectory", "trajectory.steps", t0["qpos"].size(), t1["qpos"].size(),
           "trajectory length: " + std::to_string(t0["qpos"].size()) + " → " +
               std::to_string(t1["qpos"].size()) + " steps");
  }
  bool shapes = before["sizes"]["nq"] == after["sizes"]["nq"] &&
                before["sizes"]["nv"] == after["sizes"]["nv"] &&
                before["sizes"]["na"] == after["sizes"]["na"];
  if (!shapes) {
    if (!t0["qpos"].empty() && !t1["qpos"].empty()) {
      change("trajectory", "trajectory", nullptr, nullptr,
             "trajectory not compared: the state's size changed");
    }
  } else {
    std::size_t steps = std::min(t0["qpos"].size(), t1["qpos"].size());
    for (std::size_t s = 0; s < steps; ++s) {
      std::string worst_field, worst_at, worst_path;
      double worst = 0, worst_was = 0, worst_is = 0;
      bool departs = false;
      for (const char* field : {"qpos", "qvel", "act"}) {
        const ordered_json& a = t0[field][s];
        const ordered_json& b = t1[field][s];
        for (std::size_t i = 0; i < a.size() && i < b.size(); ++i) {
          double x = a[i].get<double>(), y = b[i].get<double>();
          if (!CloseTrajectory(x, y, tol)) departs = true;
          if (std::fabs(x - y) > worst) {
            worst = std::fabs(x - y);
            worst_field = field;
            worst_at = StateElement(model, field, i);
            worst_path = std::string("trajectory.") + field + "[" + std::to_string(i) + "]";
            worst_was = x;
            worst_is = y;
          }
        }
      }
      if (departs) {
        char buffer[64];
        std::snprintf(buffer, sizeof(buffer), "%.2g (tol %g)", worst, tol);
        change("trajectory", worst_path, worst_was, worst_is,
               "trajectory departs at step " + std::to_string(s + 1) + ": max |Δ" + worst_field +
                   "| = " + buffer + " at " + worst_at);
        diff.changes.back().step = static_cast<long>(s + 1);
        break;
      }
    }
  }
  if (diff.diverged) {
    change("trajectory", "trajectory", nullptr, nullptr,
           "the golden trajectory diverges on the current model: " + diverged +
               " Fix: look at the changes above; a smaller timestep, joint damping or armature, "
               "or softer contacts keep it finite.");
  }
  return diff;
}

}  // namespace plumb
