// Writing and validating values: what a path may be set to (types, domains), how a write
// keeps the model consistent (a new mass keeps the body's shape; constants recomputed),
// and PATH=VALUE assignments. Resolving the names is path.cc.

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <optional>

#include "core/fields.h"
#include "core/path_internal.h"
#include "core/strings.h"
#include "plumb/error.h"
#include "plumb/path.h"

namespace plumb {
using internal::ElemSize;
using internal::EqualsIgnoreCase;
using internal::FieldBase;
using internal::FieldInfo;
using internal::Fields;
using internal::FieldSource;
using internal::FormatNumber;
using internal::IsCompilerConstant;
using internal::Join;
using internal::JointDofSize;
using internal::JointQposSize;
using internal::ParseNumber;
using internal::Split;
using internal::WriteElement;

namespace {

using compat::ElemType;

// Throws ValueError unless `v` can be stored in an element of `type`.
void CheckValue(ElemType type, const std::string& where, double v) {
  if (!std::isfinite(v)) {
    throw ValueError("value for '" + where + "' is " + std::to_string(v) +
                     ": NaN and Inf are not allowed.");
  }
  auto require_integral = [&](double lo, double hi) {
    if (v != std::floor(v) || v < lo || v > hi) {
      throw ValueError("'" + where + "' is an integer field; " + std::to_string(v) +
                       " is not an integer between " + std::to_string(static_cast<long>(lo)) +
                       " and " + std::to_string(static_cast<long>(hi)) + ".");
    }
  };
  switch (type) {
    case ElemType::kFloat:
      if (std::fabs(v) > std::numeric_limits<float>::max()) {
        throw ValueError("value " + std::to_string(v) + " for '" + where +
                         "' does not fit a float.");
      }
      break;
    case ElemType::kInt:
      require_integral(std::numeric_limits<int>::min(), std::numeric_limits<int>::max());
      break;
    case ElemType::kInt64:
      require_integral(-9.0e15, 9.0e15);
      break;
    case ElemType::kByte:
      require_integral(0, 255);
      break;
    case ElemType::kBool:
      require_integral(0, 1);
      break;
    default:
      break;
  }
}

// Throws PathError explaining why `path` cannot be set, unless it can.
void RequireWritable(const Path& path) {
  if (path.writable) return;
  const FieldInfo& field = Fields()[path.field_index];
  std::string why;
  if (field.name == std::string("history")) {
    why =
        "it is MuJoCo's ring buffer of past controls and sensor values, which actuator and "
        "sensor delays read: mj_step writes it and a reset or keyframe fills it; set ctrl "
        "instead.";
  } else if (path.role == Role::kDerived) {
    why =
        "it is derived: MuJoCo computes it from the state (qpos, qvel, act) and inputs "
        "(ctrl) in mj_forward/mj_step; set those instead.";
  } else if (IsCompilerConstant(field.name)) {
    why =
        "it is a constant the compiler derives (mj_setConst recomputes it); change the "
        "quantities it comes from instead (e.g. body_mass, body_inertia).";
  } else {
    why =
        "it describes the model's structure (sizes, addresses, ids, types), which "
        "cannot change after compilation; edit the MJCF instead.";
  }
  throw PathError("cannot set '" + path.text + "': " + why);
}

// A body whose mass changes keeps its shape and mass distribution: its principal
// moments of inertia scale by new mass / old mass (a massless body keeps its inertia).
void KeepShape(mjModel* m, const Path& mass, const std::vector<double>& values) {
  for (long k = 0; k < mass.count; ++k) {
    long body = mass.first + k;
    double old_mass = m->body_mass[body];
    if (!(old_mass > 0) || values[k] == old_mass) continue;
    for (int i = 0; i < 3; ++i) m->body_inertia[3 * body + i] *= values[k] / old_mass;
  }
}

void* MutableElement(Model& model, Data& data, const Path& path, long k) {
  const FieldInfo& field = Fields()[path.field_index];
  const void* base = FieldBase(field, model.get(), data.get());
  return const_cast<char*>(static_cast<const char*>(base)) +
         (path.first + k) * ElemSize(field.type);
}

}  // namespace

void WriteValues(Model& model, Data& data, const Path& path, const std::vector<double>& values) {
  const FieldInfo& field = Fields()[path.field_index];
  RequireWritable(path);
  if (path.bit >= 0) {
    // one flag: 0 or 1 into its bit, the other flags as they are
    if (values.size() != 1 || (values[0] != 0 && values[0] != 1)) {
      throw ValueError("'" + path.text + "' is one flag: give 0 (off) or 1 (on).");
    }
    Path whole = path;
    whole.bit = -1;
    long long mask = ReadValue(model, data, whole);
    long long bit = 1LL << path.bit;
    WriteValues(model, data, whole,
                {static_cast<double>(values[0] != 0 ? mask | bit : mask & ~bit)});
    return;
  }
  if (static_cast<long>(values.size()) != path.count) {
    throw ValueError("'" + path.text + "' takes " + std::to_string(path.count) + " value(s), got " +
                     std::to_string(values.size()) + ".");
  }
  for (double v : values) CheckValue(field.type, path.text, v);
  if (path.field == "body_mass") KeepShape(model.get_mutable(), path, values);
  for (long k = 0; k < path.count; ++k) {
    double v = values[k];
    void* at = MutableElement(model, data, path, k);
    if (!WriteElement(field.type, at, v)) {
      throw PathError("cannot set '" + path.text + "': it is not numeric.");
    }
  }
}

namespace {

// MJCF names of enumerated options, accepted as values.
const compat::EnumName* EnumTable(const std::string& field, std::size_t* size) {
  if (field == "opt.integrator") {
    *size = std::size(compat::kIntegrators);
    return compat::kIntegrators;
  }
  if (field == "opt.cone") {
    *size = std::size(compat::kCones);
    return compat::kCones;
  }
  if (field == "opt.solver") {
    *size = std::size(compat::kSolvers);
    return compat::kSolvers;
  }
  if (field == "opt.jacobian") {
    *size = std::size(compat::kJacobians);
    return compat::kJacobians;
  }
  *size = 0;
  return nullptr;
}

// The smallest value MuJoCo's compiler accepts for a field, where it checks one (a
// negative mass or iteration count compiles from no XML and breaks the solver at run time).
struct Bound {
  const char* field;
  double min;
  bool strict;  // > min rather than >= min
  const char* what;
};
constexpr Bound kBounds[] = {
    {"opt.timestep", 0, true, "the timestep must be positive"},
    {"opt.impratio", 0, true, "the friction-to-normal impedance ratio must be positive"},
    {"opt.iterations", 1, false, "the solver needs at least one iteration"},
    {"opt.ls_iterations", 1, false, "the line search needs at least one iteration"},
    {"opt.noslip_iterations", 0, false, "an iteration count cannot be negative"},
    {"opt.mpr_iterations", 0, false, "an iteration count cannot be negative"},
    {"opt.tolerance", 0, false, "a tolerance cannot be negative"},
    {"opt.ls_tolerance", 0, false, "a tolerance cannot be negative"},
    {"opt.noslip_tolerance", 0, false, "a tolerance cannot be negative"},
    {"opt.mpr_tolerance", 0, false, "a tolerance cannot be negative"},
    {"opt.density", 0, false, "a medium density cannot be negative"},
    {"opt.viscosity", 0, false, "a viscosity cannot be negative"},
    {"body_mass", 0, false, "a mass cannot be negative"},
    {"body_inertia", 0, false, "principal moments of inertia cannot be negative"},
    {"dof_armature", 0, false, "armature (rotor inertia) cannot be negative"},
    {"dof_frictionloss", 0, false, "friction loss cannot be negative"},
    {"geom_margin", 0, false, "a contact margin cannot be negative"},
};

// Throws ValueError when the values parse but MuJoCo would reject or misread them: an
// enumerated option outside its names, a geom's condim other than 1, 3, 4, 6, option
// flags beyond the defined bits, or a value below a field's bound.
void CheckDomain(const Path& path, const std::string& text, const std::vector<double>& values) {
  std::size_t enum_size = 0;
  const compat::EnumName* names = EnumTable(path.field, &enum_size);
  const std::string& field = path.field;
  auto fail = [&](const std::string& why) {
    throw ValueError((text.empty() ? "" : text + ": ") + why + ".");
  };
  for (double v : values) {
    if (names) {
      bool known = false;
      std::vector<std::string> valid;
      for (std::size_t i = 0; i < enum_size; ++i) {
        known = known || names[i].value == v;
        valid.push_back(std::string(names[i].name) + " (" + std::to_string(names[i].value) + ")");
      }
      if (!known)
        fail(FormatNumber(v) + " is not a valid " + field + "; valid: " + Join(valid, ", "));
    }
    if (field == "geom_condim" && v != 1 && v != 3 && v != 4 && v != 6) {
      fail("a geom's condim is 1, 3, 4 or 6 (frictionless, sliding, +torsional, +rolling)");
    }
    if (field == "opt.disableflags" && (v < 0 || v >= (1 << mjNDISABLE))) {
      fail("disable flags are bits 0.." + std::to_string(mjNDISABLE - 1) + ": a value from 0 to " +
           std::to_string((1 << mjNDISABLE) - 1));
    }
    if (field == "opt.enableflags" && (v < 0 || v >= (1 << mjNENABLE))) {
      fail("enable flags are bits 0.." + std::to_string(mjNENABLE - 1) + ": a value from 0 to " +
           std::to_string((1 << mjNENABLE) - 1));
    }
    for (const Bound& bound : kBounds) {
      if (field != bound.field) continue;
      if (bound.strict ? v <= bound.min : v < bound.min) {
        fail(std::string(bound.what) + " (got " + FormatNumber(v) + ")");
      }
    }
  }
}

}  // namespace

namespace {

// "a block of 7 values (free joint: x, y, z, then quaternion w, x, y, z)".
std::string BlockDescription(const Model& model, const Path& path) {
  const mjModel* m = model.get();
  std::string block = path.count == 1 ? std::string("a single value")
                                      : "a block of " + std::to_string(path.count) + " values";
  for (int j = 0; j < m->njnt; ++j) {
    int type = m->jnt_type[j];
    if (type != mjJNT_FREE && type != mjJNT_BALL) continue;
    bool is_qpos = path.field == "qpos" && path.first == m->jnt_qposadr[j] &&
                   path.count == JointQposSize(type);
    bool is_dof = path.first == m->jnt_dofadr[j] && path.count == JointDofSize(type) &&
                  Fields()[path.field_index].row_kind == "nv";
    if (!is_qpos && !is_dof) continue;
    if (is_qpos) {
      return block + (type == mjJNT_FREE
                          ? " (a free joint: position x, y, z, then orientation quaternion w, x, "
                            "y, z, which MuJoCo normalises)"
                          : " (a ball joint: orientation quaternion w, x, y, z, which MuJoCo "
                            "normalises)");
    }
    return block + (type == mjJNT_FREE ? " (a free joint's 6 dofs: linear x, y, z, then angular "
                                         "x, y, z)"
                                       : " (a ball joint's 3 rotational dofs)");
  }
  return block;
}

// Warnings for quaternions of free and ball joints written whole in a qpos assignment
// whose norm is not 1: MuJoCo normalises them in mj_forward.
std::vector<std::string> QuaternionWarnings(const Model& model, const Assignment& a) {
  const mjModel* m = model.get();
  std::vector<std::string> warnings;
  if (a.path.field != "qpos") return warnings;
  for (int j = 0; j < m->njnt; ++j) {
    if (m->jnt_type[j] != mjJNT_FREE && m->jnt_type[j] != mjJNT_BALL) continue;
    long q = m->jnt_qposadr[j] + (m->jnt_type[j] == mjJNT_FREE ? 3 : 0);
    if (q < a.path.first || q + 4 > a.path.first + a.path.count) continue;
    const double* w = a.values.data() + (q - a.path.first);
    double norm = std::sqrt(w[0] * w[0] + w[1] * w[1] + w[2] * w[2] + w[3] * w[3]);
    if (std::fabs(norm - 1) <= 1e-4) continue;
    std::string name = model.Name(mjOBJ_JOINT, j);
    warnings.push_back("the orientation quaternion of joint " +
                       (name.empty() ? "#" + std::to_string(j) : "'" + name + "'") + " (qpos[" +
                       std::to_string(q) + "..." + std::to_string(q + 3) + "]) has norm " +
                       FormatNumber(norm) +
                       (norm > 0 ? "; MuJoCo normalises it to unit length."
                                 : "; MuJoCo replaces it with the identity (1, 0, 0, 0)."));
  }
  return warnings;
}

// What MuJoCo will silently change about an assignment: a ctrl (or act) outside the
// actuator's ctrlrange (actrange) is clamped to it at every step; a quaternion is
// normalised.
std::vector<std::string> SilentChangeWarnings(const Model& model, const Assignment& a) {
  const mjModel* m = model.get();
  std::vector<std::string> warnings = QuaternionWarnings(model, a);
  bool is_ctrl = a.path.field == "ctrl";
  if (!is_ctrl && a.path.field != "act") return warnings;
  if (is_ctrl && (m->opt.disableflags & mjDSBL_CLAMPCTRL)) return warnings;
  for (long k = 0; k < a.path.count; ++k) {
    long row = a.path.first + k;
    // ctrlrange has a row per control, actrange one per actuator
    int id = is_ctrl ? compat::ControlActuator(m, row) : -1;
    for (int u = 0; !is_ctrl && u < compat::ActuatorCount(m) && id < 0; ++u) {
      if (compat::ActuatorActAddress(m, u) == row) id = u;
    }
    if (id < 0) continue;
    bool limited = is_ctrl ? m->actuator_ctrllimited[row] : m->actuator_actlimited[id];
    if (!limited) continue;
    const mjtNum* range = is_ctrl ? m->actuator_ctrlrange + 2 * row : m->actuator_actrange + 2 * id;
    double v = a.values[k];
    if (v >= range[0] && v <= range[1]) continue;
    std::string name = model.Name(mjOBJ_ACTUATOR, id);
    std::string actuator = name.empty() ? "#" + std::to_string(id) : "'" + name + "'";
    double clamped = std::clamp(v, range[0], range[1]);
    warnings.push_back(FormatNumber(v) + " is outside the " + (is_ctrl ? "ctrlrange" : "actrange") +
                       " [" + FormatNumber(range[0]) + ", " + FormatNumber(range[1]) +
                       "] of actuator " + actuator +
                       "; MuJoCo clamps it, so the actuator acts as if " + a.path.field + " = " +
                       FormatNumber(clamped) + ".");
  }
  return warnings;
}

}  // namespace

Assignment ParseAssignment(const Model& model, std::string_view text) {
  auto [path_text, value_view] =
      SplitAssignment(text, "set", "PATH=VALUE, e.g. qpos[hinge]=0.7 or opt.gravity=0,0,-1.62");
  Assignment a;
  a.text = std::string(text);
  a.path = ResolvePath(model, path_text);
  std::string value_text(value_view);
  std::size_t enum_size = 0;
  const compat::EnumName* names = EnumTable(a.path.field, &enum_size);
  for (const std::string& item : Split(value_text, ',')) {
    std::optional<double> v = ParseNumber(item);
    if (!v && names) {
      for (std::size_t i = 0; i < enum_size; ++i) {
        if (EqualsIgnoreCase(item, names[i].name)) v = names[i].value;
      }
      if (!v) {
        std::vector<std::string> valid;
        for (std::size_t i = 0; i < enum_size; ++i) valid.push_back(names[i].name);
        throw ArgumentError("set", Quoted(a.text),
                            "'" + item + "' is not a valid " + a.path.field +
                                "; valid names: " + Join(valid, ", ") + ".");
      }
    }
    if (!v) {
      throw ArgumentError("set", Quoted(a.text), "'" + item + "' is not a number.");
    }
    if (!std::isfinite(*v)) {
      throw ArgumentError("set", Quoted(a.text), item + " is not a finite number.");
    }
    a.values.push_back(*v);
  }
  if (static_cast<long>(a.values.size()) != a.path.count) {
    throw ArgumentError("set", Quoted(a.text),
                        "'" + a.path.text + "' is " + BlockDescription(model, a.path) +
                            "; give exactly " + std::to_string(a.path.count) +
                            " values separated by commas (got " + std::to_string(a.values.size()) +
                            "), or set one element, e.g. " + a.path.text +
                            "[0]=" + FormatNumber(a.values.front()) + ".");
  }
  RequireWritable(a.path);
  for (double v : a.values) CheckValue(Fields()[a.path.field_index].type, a.text, v);
  try {
    CheckDomain(a.path, "", a.values);
  } catch (const ValueError& e) {
    throw ArgumentError("set", Quoted(a.text), e.what());
  }
  a.warnings = SilentChangeWarnings(model, a);
  return a;
}

void CheckAssignable(const Path& path, double value) {
  CheckValue(Fields()[path.field_index].type, path.text, value);
  CheckDomain(path, "'" + path.text + "' = " + FormatNumber(value), {value});
}

std::pair<std::string_view, std::string_view> SplitAssignment(std::string_view text,
                                                              const char* argument,
                                                              const char* example) {
  std::size_t eq = text.find('=');
  if (eq == std::string_view::npos) {
    throw ArgumentError(argument, Quoted(std::string(text)),
                        std::string("expected ") + example + ".");
  }
  return {text.substr(0, eq), text.substr(eq + 1)};
}

bool ChangesModelArrays(const Path& path) {
  return Fields()[path.field_index].source == FieldSource::kModelArray;
}

bool WriteParameters(Model& model, Data& data, const std::vector<Assignment>& assignments) {
  bool arrays_changed = false;
  for (bool inertia : {false, true}) {
    for (const Assignment& a : assignments) {
      if (a.path.role != Role::kParameter || (a.path.field == "body_inertia") != inertia) continue;
      WriteValues(model, data, a.path, a.values);
      arrays_changed = arrays_changed || ChangesModelArrays(a.path);
    }
  }
  return arrays_changed;
}

void WriteState(Model& model, Data& data, const std::vector<Assignment>& assignments) {
  for (const Assignment& a : assignments) {
    if (a.path.role != Role::kParameter) WriteValues(model, data, a.path, a.values);
  }
}

void ApplyAssignments(Model& model, Data& data, const std::vector<Assignment>& assignments) {
  // parameters first: the state edits below may depend on them (qpos0, sizes)
  // recompute constants derived from masses, inertias and qpos0 (uses its own data:
  // mj_setConst overwrites the state it is given)
  if (WriteParameters(model, data, assignments)) {
    Data scratch(model);
    mj_setConst(model.get_mutable(), scratch.get());
  }
  data.Reset();
  WriteState(model, data, assignments);
  // the chapter's rule: after setting state, make derived quantities consistent
  data.Forward();
}

}  // namespace plumb
