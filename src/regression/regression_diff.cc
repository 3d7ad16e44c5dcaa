// plumb diff: a snapshot against the current model, change by change: sizes, options, every
// recorded field of every element, and where the golden trajectory departs.

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <set>

#include "core/fields.h"
#include "core/mujoco_compat.h"
#include "plumb/error.h"
#include "plumb/regression.h"
#include "regression/regression_internal.h"

namespace plumb {
using internal::kSnapshotFormat;
using internal::SnapshotElementName;
using internal::SnapshotJson;
using nlohmann::ordered_json;

namespace {

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
        value =
            same ? *named : "type " + std::to_string(number) + " as numbered by MuJoCo " + writer;
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
  if (!(version >= 1 && version <= kSnapshotFormat)) {
    throw ValueError("plumb_snapshot: version " + version.dump() +
                     " is not one this plumb reads (1 to " + std::to_string(kSnapshotFormat) +
                     "): a newer plumb wrote it");
  }
  Member(before, "", "mujoco_version", &J::is_string, "a string");
  if (before.contains("sets")) {  // snapshots written before assignments were recorded lack it
    const J& sets = Member(before, "", "sets", &J::is_array, "an array of assignments");
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
      if (m->jnt_qposadr[j] <= n)
        return label + " (joint '" + SnapshotElementName(model, mjOBJ_JOINT, j) + "')";
    }
  } else if (array == "qvel" && n < m->nv) {
    return label + " (joint '" + SnapshotElementName(model, mjOBJ_JOINT, m->dof_jntid[n]) + "')";
  } else if (array == "act" && n < m->na) {
    for (int u = compat::ActuatorCount(m) - 1; u >= 0; --u) {
      int adr = compat::ActuatorActAddress(m, u);
      if (adr >= 0 && adr <= n) {
        return label + " (actuator '" + SnapshotElementName(model, mjOBJ_ACTUATOR, u) + "')";
      }
    }
  }
  return label;
}

// How a diff names element `key` of `section` in words: its name, or for an unnamed one ("#15")
// its number and the body it hangs on, "geom #15 of body 'left_ankle_roll_link'".
std::string ElementWords(const std::string& section, const std::string& key,
                         const ordered_json& fields) {
  if (key.empty() || key[0] != '#') return key;
  const std::string body_field = section + "_bodyid";
  if (section == "body" || !fields.contains(body_field) || !fields[body_field].is_string()) {
    return section + " " + key;
  }
  return section + " " + key + " of body '" + fields[body_field].get<std::string>() + "'";
}

// Builds a SnapshotDiff step by step: `before` is the snapshot read back, `after` the current
// model's.
class Differ {
 public:
  Differ(const ordered_json& before, const ordered_json& after, double tol, SnapshotDiff* diff)
      : before_(before),
        after_(after),
        tol_(tol),
        diff_(diff),
        other_version_(before["mujoco_version"] != after["mujoco_version"]) {}

  void Change(const char* kind, std::string path, const ordered_json& was, const ordered_json& is,
              std::string what) {
    SnapshotChange c;
    c.what = std::move(what);
    c.kind = kind;
    c.path = std::move(path);
    c.old_value = was.dump();
    c.new_value = is.dump();
    diff_->changes.push_back(std::move(c));
  }

  void Sizes() {
    const ordered_json none;
    for (const auto& [key, value] : after_["sizes"].items()) {
      auto old = before_["sizes"].find(key);
      const ordered_json& was = old == before_["sizes"].end() ? none : *old;
      if (was != value)
        Change("structure", key, was, value, key + ": " + Show(was) + " → " + Show(value));
    }
  }

  void Options() {
    for (const auto& [key, value] : after_["options"].items()) {
      auto old = before_["options"].find(key);
      if (old == before_["options"].end()) continue;
      if (!Same(*old, value, tol_)) {
        Change("option", key, *old, value, key + ": " + Show(*old) + " → " + Show(value));
      }
    }
  }

  void Structure() {
    for (const auto& [section, elements] : after_["structure"].items()) {
      auto found = before_["structure"].find(section);
      // format 1 predates keyframes: nothing to compare them with (Notes says so)
      if (found == before_["structure"].end() && section == "keyframe") continue;
      const ordered_json empty = ordered_json::object();
      Section(section, found == before_["structure"].end() ? empty : *found, elements);
    }
  }

  // The golden trajectory, step by step: the first step where it departs.
  void Trajectory(const Model& model, const std::string& diverged) {
    const ordered_json& t0 = before_["trajectory"];
    const ordered_json& t1 = after_["trajectory"];
    if (t0["qpos"].size() != t1["qpos"].size() && diverged.empty()) {
      Change("trajectory", "trajectory.steps", t0["qpos"].size(), t1["qpos"].size(),
             "trajectory length: " + std::to_string(t0["qpos"].size()) + " → " +
                 std::to_string(t1["qpos"].size()) + " steps");
    }
    bool shapes = before_["sizes"]["nq"] == after_["sizes"]["nq"] &&
                  before_["sizes"]["nv"] == after_["sizes"]["nv"] &&
                  before_["sizes"]["na"] == after_["sizes"]["na"];
    if (!shapes) {
      if (!t0["qpos"].empty() && !t1["qpos"].empty()) {
        Change("trajectory", "trajectory", nullptr, nullptr,
               "trajectory not compared: the state's size changed");
      }
    } else {
      std::size_t steps = std::min(t0["qpos"].size(), t1["qpos"].size());
      for (std::size_t s = 0; s < steps; ++s) {
        if (Departs(model, t0, t1, s)) break;
      }
    }
    if (!diverged.empty()) {
      Change("trajectory", "trajectory", nullptr, nullptr,
             "the golden trajectory diverges on the current model: " + diverged +
                 " Fix: look at the changes above; a smaller timestep, joint damping or "
                 "armature, or softer contacts keep it finite.");
    }
  }

 private:
  // What MuJoCo's compiler derives from a mesh geom's vertices (its fitted primitive's size,
  // frame and bounding box; and from them each dof's length scale): releases fit them
  // differently from the same mesh file.
  bool CompilerDerived(const std::string& section, const ordered_json& fields,
                       const std::string& field) const {
    static const std::set<std::string> kMeshDerived = {"geom_size", "geom_aabb", "geom_pos",
                                                       "geom_quat", "geom_rbound"};
    bool mesh_derived =
        section == "geom" && fields.value("geom_type", "") == "mesh" && kMeshDerived.count(field);
    // a dof's length scale comes from the size of the bodies it moves
    bool size_derived = section == "dof" && field == "dof_length";
    return other_version_ && (mesh_derived || size_derived);
  }

  // One section ("body", "joint", ...): elements removed and added, fields changed, ids
  // shifted (one change for the whole section).
  void Section(const std::string& section, const ordered_json& old, const ordered_json& elements) {
    for (const auto& [name, fields] : old.items()) {
      if (!elements.contains(name)) {
        Change("removed", section + "[" + name + "]", fields["id"], nullptr,
               section + " removed: " + ElementWords(section, name, fields));
      }
    }
    int renumbered = 0;
    std::string first_renumbered;
    ordered_json first_was, first_is;
    for (const auto& [name, fields] : elements.items()) {
      if (!old.contains(name)) {
        Change("added", section + "[" + name + "]", nullptr, fields["id"],
               section + " added: " + ElementWords(section, name, fields) + " (id " +
                   Show(fields["id"]) + ")");
        continue;
      }
      const ordered_json& was = old[name];
      if (was.contains("id") && fields.contains("id") && was["id"] != fields["id"] &&
          renumbered++ == 0) {
        first_renumbered = name + ": " + Show(was["id"]) + " → " + Show(fields["id"]);
        first_was = was["id"];
        first_is = fields["id"];
      }
      Fields(section, name, was, fields);
    }
    if (renumbered > 0) {
      Change("structure", section + " ids", first_was, first_is,
             section + " ids shift: " + std::to_string(renumbered) + " renumbered (first " +
                 first_renumbered + "); code that indexes " + section + "s by id must follow");
    }
  }

  // The fields of one element present in both snapshots (ids are compared per section).
  void Fields(const std::string& section, const std::string& name, const ordered_json& was,
              const ordered_json& fields) {
    for (const auto& [field, value] : fields.items()) {
      if (field == "id" || !was.contains(field) || Same(was[field], value, tol_)) continue;
      // what an element is and where it hangs is structure; its numbers are parameters
      bool structural = value.is_string() ||
                        (field.size() > 5 && field.compare(field.size() - 5, 5, "_type") == 0);
      std::string path = field + "[" + name + "]";
      std::string what = path + ": " + Show(was[field]) + " → " + Show(value);
      if (!name.empty() && name[0] == '#') {
        what += " (" + ElementWords(section, name, fields) + ")";
      }
      if (CompilerDerived(section, fields, field)) {
        // the same mesh, fitted by another release's compiler: not the user's change
        Change("compiler", path, was[field], value, what);
        diff_->compiler.push_back(diff_->changes.back());
        diff_->changes.pop_back();
        continue;
      }
      Change(structural ? "structure" : "parameter", path, was[field], value, what);
    }
  }

  // Whether the trajectories part at step s (0-based): then one change naming the element
  // that moved furthest.
  bool Departs(const Model& model, const ordered_json& t0, const ordered_json& t1, std::size_t s) {
    std::string worst_field, worst_at, worst_path;
    double worst = 0, worst_was = 0, worst_is = 0;
    bool departs = false;
    for (const char* field : {"qpos", "qvel", "act"}) {
      const ordered_json& a = t0[field][s];
      const ordered_json& b = t1[field][s];
      for (std::size_t i = 0; i < a.size() && i < b.size(); ++i) {
        double x = a[i].get<double>(), y = b[i].get<double>();
        if (!CloseTrajectory(x, y, tol_)) departs = true;
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
    if (!departs) return false;
    char buffer[64];
    std::snprintf(buffer, sizeof(buffer), "%.2g (tol %g)", worst, tol_);
    Change("trajectory", worst_path, worst_was, worst_is,
           "trajectory departs at step " + std::to_string(s + 1) + ": max |Δ" + worst_field +
               "| = " + buffer + " at " + worst_at);
    diff_->changes.back().step = static_cast<long>(s + 1);
    return true;
  }

  const ordered_json& before_;
  const ordered_json& after_;
  double tol_;
  SnapshotDiff* diff_;
  bool other_version_;
};

// The snapshot's own --set texts, parsed against the current model: those that apply, and
// those that no longer do with the reason.
std::vector<Assignment> SnapshotSets(const Model& model, const ordered_json& parsed,
                                     SnapshotDiff* diff,
                                     std::vector<std::pair<std::string, std::string>>* refused) {
  std::vector<Assignment> out;
  if (!parsed.contains("sets") || !parsed["sets"].is_array()) return out;
  for (const ordered_json& text : parsed["sets"]) {
    if (!text.is_string()) continue;  // ValidateSnapshot names it
    try {
      out.push_back(ParseAssignment(model, text.get<std::string>()));
      diff->sets.push_back(text.get<std::string>());
    } catch (const Error& e) {
      refused->emplace_back(text.get<std::string>(), e.what());
    }
  }
  return out;
}

// The notes above the changes: another MuJoCo (the assignments the model ran with are
// SnapshotDiff::sets, which the writers show).
void Notes(const ordered_json& before, const ordered_json& after, SnapshotDiff* diff) {
  if (!before["structure"].contains("keyframe") && after["sizes"]["nkey"] != 0) {
    diff->notes.push_back("the snapshot (format " + before["plumb_snapshot"].dump() +
                          ") predates keyframes, so they are not compared: write it again to "
                          "include them");
  }
  if (before["mujoco_version"] != after["mujoco_version"]) {
    diff->notes.push_back("the snapshot was written with MuJoCo " +
                          before["mujoco_version"].get<std::string>() + ", this is " +
                          after["mujoco_version"].get<std::string>() +
                          ": trajectories differ in the last bits across versions");
  }
}

}  // namespace

SnapshotDiff DiffSnapshot(const std::string& text, const Model& model,
                          const std::vector<Assignment>& sets, double tol) {
  if (!(tol >= 0)) throw ArgumentError("tol", fmt::format("{:g}", tol), "must be >= 0");
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
  diff.model = model.file();
  diff.tol = tol;
  for (const Assignment& a : sets) diff.model_sets.push_back(a.text);
  // the snapshot's own --set values first, then the caller's (which win)
  std::vector<std::pair<std::string, std::string>> refused;  // text, reason
  std::vector<Assignment> all = SnapshotSets(model, parsed, &diff, &refused);
  all.insert(all.end(), sets.begin(), sets.end());
  std::string diverged;
  const ordered_json after = SnapshotJson(model, all, &diverged);
  NameNumberedEnums(&parsed);
  const ordered_json& before = parsed;  // const: a missing key can never be inserted
  ValidateSnapshot(before, after);
  diff.diverged = !diverged.empty();
  diff.snapshot_mujoco_version = before["mujoco_version"].get<std::string>();
  if (before.contains("plumb_version") && before["plumb_version"].is_string()) {
    diff.snapshot_plumb_version = before["plumb_version"].get<std::string>();
  }
  Differ differ(before, after, tol, &diff);
  for (const auto& [text, reason] : refused) {
    differ.Change("set", text, text, nullptr,
                  "the snapshot's assignment '" + text + "' does not apply to the current model (" +
                      reason + "); compared without it");
  }
  Notes(before, after, &diff);
  differ.Sizes();
  differ.Options();
  differ.Structure();
  differ.Trajectory(model, diverged);
  return diff;
}

}  // namespace plumb
