// Resolving path names to rows of mjModel, mjData and mjOption: parsing, row names, roles,
// option flags and "*" expansion. Reading values at a sample is path_read.cc; writing them is
// path_values.cc.

#include "plumb/path.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <optional>

#include "core/fields.h"
#include "core/path_internal.h"
#include "core/strings.h"
#include "plumb/error.h"

namespace plumb {
using internal::DidYouMean;
using internal::FieldInfo;
using internal::Fields;
using internal::FieldSource;
using internal::FindField;
using internal::Join;
using internal::JointDofSize;
using internal::JointQposSize;
using internal::Lowercase;
using internal::ParseIndex;
using internal::Plural;

namespace {

using compat::ElemType;

// How the rows of an array are named: the mjModel size counting them tells which
// object type names them and how a name maps to a block of rows.
enum class RowMap { kDirect, kQpos, kDof, kAct, kCtrl, kOut, kMocap, kAdrNum };

struct RowKind {
  const char* size;  // "nbody", "nq", ...
  int obj;           // mjOBJ_* naming the rows
  RowMap map;
  const char* noun;  // for messages
};

constexpr RowKind kRowKinds[] = {
    {"nbody", mjOBJ_BODY, RowMap::kDirect, "body"},
    {"njnt", mjOBJ_JOINT, RowMap::kDirect, "joint"},
    {"ngeom", mjOBJ_GEOM, RowMap::kDirect, "geom"},
    {"nsite", mjOBJ_SITE, RowMap::kDirect, "site"},
    {"ncam", mjOBJ_CAMERA, RowMap::kDirect, "camera"},
    {"nlight", mjOBJ_LIGHT, RowMap::kDirect, "light"},
    {"nmesh", mjOBJ_MESH, RowMap::kDirect, "mesh"},
    {"nskin", mjOBJ_SKIN, RowMap::kDirect, "skin"},
    {"nhfield", mjOBJ_HFIELD, RowMap::kDirect, "height field"},
    {"ntex", mjOBJ_TEXTURE, RowMap::kDirect, "texture"},
    {"nmat", mjOBJ_MATERIAL, RowMap::kDirect, "material"},
    {"npair", mjOBJ_PAIR, RowMap::kDirect, "contact pair"},
    {"nexclude", mjOBJ_EXCLUDE, RowMap::kDirect, "contact exclude"},
    {"neq", mjOBJ_EQUALITY, RowMap::kDirect, "equality"},
    {"ntendon", mjOBJ_TENDON, RowMap::kDirect, "tendon"},
    {"nactuator", mjOBJ_ACTUATOR, RowMap::kDirect, "actuator"},
    {"nu", mjOBJ_ACTUATOR, RowMap::kCtrl, "actuator"},
    {"nout", mjOBJ_ACTUATOR, RowMap::kOut, "actuator"},
    {"nsensor", mjOBJ_SENSOR, RowMap::kDirect, "sensor"},
    {"nnumeric", mjOBJ_NUMERIC, RowMap::kDirect, "numeric"},
    {"ntext", mjOBJ_TEXT, RowMap::kDirect, "text"},
    {"ntuple", mjOBJ_TUPLE, RowMap::kDirect, "tuple"},
    {"nkey", mjOBJ_KEY, RowMap::kDirect, "keyframe"},
    {"nq", mjOBJ_JOINT, RowMap::kQpos, "joint"},
    {"nv", mjOBJ_JOINT, RowMap::kDof, "joint"},
    {"na", mjOBJ_ACTUATOR, RowMap::kAct, "actuator"},
    {"nmocap", mjOBJ_BODY, RowMap::kMocap, "mocap body"},
    {"nsensordata", mjOBJ_SENSOR, RowMap::kAdrNum, "sensor"},
    {"nnumericdata", mjOBJ_NUMERIC, RowMap::kAdrNum, "numeric"},
    {"ntupledata", mjOBJ_TUPLE, RowMap::kAdrNum, "tuple"},
    {"ntextdata", mjOBJ_TEXT, RowMap::kAdrNum, "text"},
};

const RowKind* FindRowKind(const std::string& size) {
  for (const RowKind& k : kRowKinds) {
    if (size == k.size) return &k;
  }
  return nullptr;
}

// Data arrays the user may write, with their role; every other data array is derived.
struct DataRole {
  const char* name;
  Role role;
};
constexpr DataRole kWritableData[] = {
    {"qpos", Role::kState},           {"qvel", Role::kState},      {"act", Role::kState},
    {"qacc_warmstart", Role::kState}, {"ctrl", Role::kInput},      {"qfrc_applied", Role::kInput},
    {"xfrc_applied", Role::kInput},   {"mocap_pos", Role::kInput}, {"mocap_quat", Role::kInput},
    {"userdata", Role::kInput},       {"plastic", Role::kState},
};

// Model constants recomputed by the compiler and mj_setConst: writing them is undone.
constexpr const char* kConstants[] = {
    "body_subtreemass",  "body_invweight0", "dof_invweight0",   "dof_M0",      "tendon_length0",
    "tendon_invweight0", "actuator_acc0",   "actuator_length0", "cam_poscom0", "cam_pos0",
    "cam_mat0",          "light_poscom0",   "light_pos0",       "light_dir0",  "geom_rbound",
};

// Data arrays that neither mj_forward nor plumb's on-demand completion (core/derived.h)
// computes: at a sample they hold another stage's leftovers or zeros, so they are refused.
struct NotComputed {
  const char* name;
  const char* why;
};
constexpr NotComputed kNotComputed[] = {
    {"qfrc_inverse", "only mj_inverse computes it, and plumb's runs call mj_forward/mj_step"},
    {"qH", "only the Euler integrator computes it inside mj_step, for the previous step"},
    {"qHDiagInv", "only the Euler integrator computes it inside mj_step, for the previous step"},
    {"D_rownnz", "only the implicit integrator fills it inside mj_step"},
    {"D_rowadr", "only the implicit integrator fills it inside mj_step"},
    {"D_colind", "only the implicit integrator fills it inside mj_step"},
    {"qDeriv", "only the implicit integrator computes it inside mj_step, for the previous step"},
    {"qLU", "only the implicit integrator computes it inside mj_step, for the previous step"},
    // matrices over the constraint rows that MuJoCo packs with a row length of nefc, not the
    // njmax of the X-macro tables, so [row][element] would name the wrong element
    {"efc_AR", "an nefc x nefc matrix packed by the current nefc; a path cannot index it"},
    {"efc_AR_colind", "an nefc x nefc matrix packed by the current nefc; a path cannot index it"},
    {"efc_JT", "an nv x nefc matrix packed by the current nefc; a path cannot index it"},
    {"efc_JT_colind", "an nv x nefc matrix packed by the current nefc; a path cannot index it"},
};

// Integer model fields that are switches users set, not structure.
constexpr const char* kWritableIntFields[] = {
    "geom_contype",
    "geom_conaffinity",
    "geom_condim",
    "geom_priority",
    "geom_group",
    "jnt_limited",
    "jnt_group",
    "tendon_limited",
    "eq_active",
    "actuator_ctrllimited",
    "actuator_forcelimited",
    "actuator_actlimited",
    "actuator_group",
    "light_active",
    "site_group",
    "tendon_group",
};

template <std::size_t N>
bool Contains(const char* const (&list)[N], const std::string& name) {
  for (const char* item : list) {
    if (name == item) return true;
  }
  return false;
}

struct Access {
  Role role;
  bool writable;
};

Access AccessOf(const FieldInfo& field) {
  switch (field.source) {
    case FieldSource::kModelArray: {
      bool numeric = field.type == ElemType::kNum || field.type == ElemType::kFloat;
      bool writable =
          numeric ? !Contains(kConstants, field.name) : Contains(kWritableIntFields, field.name);
      return {Role::kParameter, writable};
    }
    case FieldSource::kModelSize:
      return {Role::kParameter, false};
    case FieldSource::kOption:
      return {Role::kParameter, true};
    case FieldSource::kDataArray:
      for (const DataRole& w : kWritableData) {
        if (field.name == w.name) return {w.role, true};
      }
      return {Role::kDerived, false};
    case FieldSource::kDataScalar:
      if (field.name == "time") return {Role::kState, true};
      return {Role::kDerived, false};
  }
  return {Role::kDerived, false};
}

// Names of every object of type `obj` (empty names skipped).
std::vector<std::string> NamesOf(const Model& model, int obj, long count) {
  std::vector<std::string> names;
  for (long i = 0; i < count; ++i) {
    std::string name = model.Name(obj, static_cast<int>(i));
    if (!name.empty()) names.push_back(name);
  }
  return names;
}

long ObjectCount(const mjModel* m, int obj) {
  switch (obj) {
    case mjOBJ_BODY:
      return m->nbody;
    case mjOBJ_JOINT:
      return m->njnt;
    case mjOBJ_GEOM:
      return m->ngeom;
    case mjOBJ_SITE:
      return m->nsite;
    case mjOBJ_CAMERA:
      return m->ncam;
    case mjOBJ_LIGHT:
      return m->nlight;
    case mjOBJ_MESH:
      return m->nmesh;
    case mjOBJ_SKIN:
      return m->nskin;
    case mjOBJ_HFIELD:
      return m->nhfield;
    case mjOBJ_TEXTURE:
      return m->ntex;
    case mjOBJ_MATERIAL:
      return m->nmat;
    case mjOBJ_PAIR:
      return m->npair;
    case mjOBJ_EXCLUDE:
      return m->nexclude;
    case mjOBJ_EQUALITY:
      return m->neq;
    case mjOBJ_TENDON:
      return m->ntendon;
    case mjOBJ_ACTUATOR:
      return compat::ActuatorCount(m);
    case mjOBJ_SENSOR:
      return m->nsensor;
    case mjOBJ_NUMERIC:
      return m->nnumeric;
    case mjOBJ_TEXT:
      return m->ntext;
    case mjOBJ_TUPLE:
      return m->ntuple;
    case mjOBJ_KEY:
      return m->nkey;
    default:
      return 0;
  }
}

// Rows [first, first + count) that object `id` of `kind` occupies; count 0 if none.
std::pair<long, long> RowsOf(const mjModel* m, const RowKind& kind, int id) {
  switch (kind.map) {
    case RowMap::kDirect:
      return {id, 1};
    case RowMap::kQpos:
      return {m->jnt_qposadr[id], JointQposSize(m->jnt_type[id])};
    case RowMap::kDof:
      return {m->jnt_dofadr[id], JointDofSize(m->jnt_type[id])};
    case RowMap::kAct: {
      int adr = compat::ActuatorActAddress(m, id);
      return {adr, adr < 0 ? 0 : 1};
    }
    case RowMap::kCtrl:
      return compat::ActuatorControls(m, id);
    case RowMap::kOut:
      return compat::ActuatorOutputs(m, id);
    case RowMap::kMocap: {
      int adr = m->body_mocapid[id];
      return {adr, adr < 0 ? 0 : 1};
    }
    case RowMap::kAdrNum:
      switch (kind.obj) {
        case mjOBJ_SENSOR:
          return {m->sensor_adr[id], m->sensor_dim[id]};
        case mjOBJ_NUMERIC:
          return {m->numeric_adr[id], m->numeric_size[id]};
        case mjOBJ_TUPLE:
          return {m->tuple_adr[id], m->tuple_size[id]};
        case mjOBJ_TEXT:
          return {m->text_adr[id], m->text_size[id]};
      }
  }
  return {0, 0};
}

std::vector<std::string> FieldNames() {
  std::vector<std::string> names;
  for (const FieldInfo& f : Fields()) names.push_back(f.name);
  return names;
}

// A path split into its parts: FIELD [ '[' row ']' [ '[' element ']' ] ].
struct Parsed {
  std::string field;
  std::vector<std::string> indices;
};

Parsed Parse(std::string_view text) {
  Parsed parsed;
  // blanks are dropped outside brackets and trimmed inside them: MJCF names may contain
  // spaces ("pinch site"), so body_mass[ pinch site ] names "pinch site"
  std::string s;
  int depth = 0;
  for (char c : text) {
    depth += c == '[' ? 1 : c == ']' ? -1 : 0;
    if (depth > 0 || (c != ' ' && c != '\t')) s += c;
  }
  std::size_t bracket = s.find('[');
  parsed.field = s.substr(0, bracket);
  auto bad = [&](const std::string& why) {
    return PathError("bad path '" + std::string(text) + "': " + why +
                     ". Paths look like qpos[hinge], xpos[link][2], opt.timestep or time.");
  };
  if (parsed.field.empty()) throw bad("it has no field name");
  for (char c : parsed.field) {
    if (!std::isalnum(static_cast<unsigned char>(c)) && c != '_' && c != '.') {
      throw bad(std::string("unexpected character '") + c + "' in the field name");
    }
  }
  std::size_t at = bracket;
  while (at != std::string::npos && at < s.size()) {
    if (s[at] != '[') throw bad("expected '[' at '" + s.substr(at) + "'");
    std::size_t close = s.find(']', at);
    if (close == std::string::npos) throw bad("a '[' is not closed");
    std::string index = s.substr(at + 1, close - at - 1);
    std::size_t first = index.find_first_not_of(" \t");
    index = first == std::string::npos
                ? ""
                : index.substr(first, index.find_last_not_of(" \t") - first + 1);
    if (index.empty()) throw bad("empty []");
    parsed.indices.push_back(index);
    at = close + 1;
  }
  if (parsed.indices.size() > 2) throw bad("at most two indices: [row][element]");
  return parsed;
}

// The field a parsed path names, when it can be read as numbers at a sample.
const FieldInfo& ReadableField(std::string_view text, const Parsed& parsed) {
  const FieldInfo* field = FindField(parsed.field);
  if (!field) {
    throw PathError("unknown field '" + parsed.field + "' in path '" + std::string(text) +
                    "': " + DidYouMean(parsed.field, FieldNames()) +
                    " Fields are the mjModel/mjData array names (qpos, qvel, ctrl, xpos, "
                    "sensordata, body_mass, dof_damping, ...), opt.<option> or time.");
  }
  if (field->type == ElemType::kOther) {
    throw PathError("field '" + field->name + "' in path '" + std::string(text) +
                    "' holds structures, not numbers, and cannot be read as a path.");
  }
  for (const NotComputed& n : kNotComputed) {
    if (field->source == FieldSource::kDataArray && field->name == n.name) {
      throw PathError("path '" + std::string(text) + "': '" + field->name +
                      "' cannot be read at the states plumb samples (" + n.why +
                      "): it would read as 0, a stale or a wrong value.");
    }
  }
  return *field;
}

// Options and scalars: a single index selects an element of the vector.
void SelectVectorElement(std::string_view text, const FieldInfo& field, const std::string& index,
                         Path* path) {
  std::optional<long> k = ParseIndex(index);
  if (!k) {
    throw PathError("path '" + std::string(text) + "': '" + field.name +
                    "' is indexed by number (0.." + std::to_string(path->count - 1) + ").");
  }
  if (*k >= path->count) {
    throw PathError("path '" + std::string(text) + "': index " + index + " is out of bounds; '" +
                    field.name + "' has " + std::to_string(path->count) + " element(s).");
  }
  path->first = *k;
  path->count = 1;
  path->text = field.name + "[" + index + "]";
}

// The rows {first, count} the first index selects: a row by number, or by the name (or
// "#id", how '*' names unnamed objects) of the object owning the rows.
std::pair<long, long> SelectRows(const Model& model, std::string_view text, const FieldInfo& field,
                                 const std::string& row) {
  const mjModel* m = model.get();
  long rows = field.rows(m);
  if (std::optional<long> index = ParseIndex(row)) {
    if (*index >= rows) {
      throw PathError("path '" + std::string(text) + "': row " + row + " is out of bounds; '" +
                      field.name + "' has " + std::to_string(rows) + " row(s) (" + field.row_kind +
                      " = " + std::to_string(rows) + ").");
    }
    return {*index, 1};
  }
  const RowKind* kind = FindRowKind(field.row_kind);
  if (!kind) {
    throw PathError("path '" + std::string(text) + "': the rows of '" + field.name +
                    "' (counted by " + field.row_kind + ") have no names; use a number from 0 to " +
                    std::to_string(rows - 1) + ".");
  }
  std::optional<long> by_id =
      row.size() > 1 && row[0] == '#' ? ParseIndex(row.substr(1)) : std::nullopt;
  int id = by_id && *by_id < ObjectCount(m, kind->obj) ? static_cast<int>(*by_id)
                                                       : mj_name2id(m, kind->obj, row.c_str());
  if (id < 0) {
    std::vector<std::string> names = NamesOf(model, kind->obj, ObjectCount(m, kind->obj));
    std::string listing = names.empty()
                              ? std::string(" This model has no named ") + kind->noun + "."
                              : " " + DidYouMean(row, names);
    throw PathError("path '" + std::string(text) + "': no " + kind->noun + " named '" + row +
                    "' (the rows of '" + field.name + "' are " + Plural(kind->noun) + ")." +
                    listing);
  }
  auto [first, count] = RowsOf(m, *kind, id);
  if (count == 0) {
    throw PathError("path '" + std::string(text) + "': " + kind->noun + " '" + row +
                    "' has no row in '" + field.name +
                    "' (for example, an actuator without "
                    "activation has no act, a body that is not mocap has no mocap_pos).");
  }
  return {first, count};
}

// The second index: an element within the row block `path` holds.
void SelectElement(std::string_view text, const std::string& index, Path* path) {
  std::optional<long> k = ParseIndex(index);
  if (!k) {
    throw PathError("path '" + std::string(text) + "': the element index '" + index +
                    "' must be a number from 0 to " + std::to_string(path->count - 1) + ".");
  }
  if (*k >= path->count) {
    throw PathError("path '" + std::string(text) + "': element " + index + " is out of bounds; '" +
                    path->text + "' has " + std::to_string(path->count) + " element(s).");
  }
  path->first += *k;
  path->count = 1;
  path->text += "[" + index + "]";
}

// Resolves one parsed path whose row index is not `*`.
Path ResolveParsed(const Model& model, std::string_view text, const Parsed& parsed);

// "opt.enableflags.sleep" and "opt.disableflags.contact": one flag of MuJoCo's option
// bitmasks by the name MuJoCo gives it (mjENABLESTRING, mjDISABLESTRING; any case).
std::optional<Path> ResolveFlag(const Model& model, std::string_view text, const Parsed& parsed) {
  struct Mask {
    const char* field;
    const char* const* names;
    int count;
  };
  const Mask masks[] = {{"opt.enableflags", mjENABLESTRING, mjNENABLE},
                        {"opt.disableflags", mjDISABLESTRING, mjNDISABLE}};
  for (const Mask& mask : masks) {
    std::string prefix = std::string(mask.field) + ".";
    if (parsed.field.rfind(prefix, 0) != 0) continue;
    std::string flag = Lowercase(parsed.field.substr(prefix.size()));
    std::vector<std::string> names;
    for (int bit = 0; bit < mask.count; ++bit) names.push_back(Lowercase(mask.names[bit]));
    auto found = std::find(names.begin(), names.end(), flag);
    if (found == names.end() || !parsed.indices.empty()) {
      throw PathError("path '" + std::string(text) + "': '" + flag + "' is not a flag of " +
                      mask.field + " in MuJoCo " + MujocoVersion() + ". " +
                      DidYouMean(flag, names) + " Flags: " + Join(names, ", ") + ".");
    }
    Parsed whole;
    whole.field = mask.field;
    Path path = ResolveParsed(model, text, whole);
    path.bit = static_cast<int>(found - names.begin());
    path.text = prefix + flag;
    return path;
  }
  return std::nullopt;
}

Path ResolveParsed(const Model& model, std::string_view text, const Parsed& parsed) {
  if (std::optional<Path> flag = ResolveFlag(model, text, parsed)) return *flag;
  const mjModel* m = model.get();
  const FieldInfo& field = ReadableField(text, parsed);
  Access access = AccessOf(field);
  Path path;
  path.field = field.name;
  path.role = access.role;
  path.writable = access.writable;
  path.field_index = static_cast<int>(&field - Fields().data());
  long cols = field.cols(m);
  path.first = 0;
  path.count = field.rows(m) * cols;
  path.text = field.name;
  if (parsed.indices.empty()) {
    if (path.count == 0) {
      throw PathError("path '" + std::string(text) + "' is empty in this model (" + field.row_kind +
                      " = 0).");
    }
    return path;
  }
  if (field.row_kind.empty()) {
    if (parsed.indices.size() > 1) {
      throw PathError("path '" + std::string(text) + "': '" + field.name +
                      "' takes a single index.");
    }
    SelectVectorElement(text, field, parsed.indices[0], &path);
    return path;
  }
  auto [row_first, row_count] = SelectRows(model, text, field, parsed.indices[0]);
  path.first = row_first * cols;
  path.count = row_count * cols;
  path.text += "[" + parsed.indices[0] + "]";
  if (parsed.indices.size() == 2) SelectElement(text, parsed.indices[1], &path);
  return path;
}

}  // namespace

bool internal::IsCompilerConstant(const std::string& field) { return Contains(kConstants, field); }

const char* RoleName(Role role) {
  switch (role) {
    case Role::kParameter:
      return "parameter";
    case Role::kState:
      return "state";
    case Role::kInput:
      return "input";
    case Role::kDerived:
      return "derived";
  }
  return "?";
}

Path ResolvePath(const Model& model, std::string_view text) {
  Parsed parsed = Parse(text);
  if (!parsed.indices.empty() && parsed.indices[0] == "*") {
    throw PathError("path '" + std::string(text) +
                    "': '*' names several rows; it is only "
                    "accepted where a list of paths is expected.");
  }
  return ResolveParsed(model, text, parsed);
}

std::vector<Path> ExpandPath(const Model& model, std::string_view text) {
  Parsed parsed = Parse(text);
  if (parsed.indices.empty() || parsed.indices[0] != "*") {
    return {ResolveParsed(model, text, parsed)};
  }
  const FieldInfo* field = FindField(parsed.field);
  if (!field) ResolveParsed(model, text, parsed);  // throws the unknown-field message
  const RowKind* kind = FindRowKind(field->row_kind);
  if (!kind) {
    throw PathError("path '" + std::string(text) + "': the rows of '" + parsed.field +
                    "' have no names, so '*' cannot expand them.");
  }
  const mjModel* m = model.get();
  std::vector<Path> paths;
  // every object with a row, named or not; the world body is not a body one randomizes
  for (long id = kind->obj == mjOBJ_BODY ? 1 : 0; id < ObjectCount(m, kind->obj); ++id) {
    if (RowsOf(m, *kind, static_cast<int>(id)).second == 0) continue;
    std::string name = model.Name(kind->obj, static_cast<int>(id));
    Parsed one = parsed;
    one.indices[0] = name.empty() ? "#" + std::to_string(id) : name;
    paths.push_back(ResolveParsed(model, text, one));
  }
  if (paths.empty()) {
    throw PathError("path '" + std::string(text) + "' matches nothing: this model has no " +
                    kind->noun + " with a row in '" + parsed.field + "'.");
  }
  return paths;
}

}  // namespace plumb
