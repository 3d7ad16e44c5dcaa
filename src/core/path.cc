#include "plumb/path.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>

#include "core/fields.h"
#include "core/strings.h"
#include "plumb/error.h"

namespace plumb {
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
    {"userdata", Role::kInput},
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

int JointQposSize(int type) { return type == mjJNT_FREE ? 7 : type == mjJNT_BALL ? 4 : 1; }
int JointDofSize(int type) { return type == mjJNT_FREE ? 6 : type == mjJNT_BALL ? 3 : 1; }

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

// Resolves one parsed path whose row index is not `*`.
Path ResolveParsed(const Model& model, std::string_view text, const Parsed& parsed) {
  const mjModel* m = model.get();
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
  Access access = AccessOf(*field);
  Path path;
  path.field = field->name;
  path.role = access.role;
  path.writable = access.writable;
  path.field_index = static_cast<int>(field - Fields().data());

  long rows = field->rows(m);
  long cols = field->cols(m);
  path.first = 0;
  path.count = rows * cols;
  std::string canonical = field->name;
  if (parsed.indices.empty()) {
    path.text = canonical;
    if (path.count == 0) {
      throw PathError("path '" + std::string(text) + "' is empty in this model (" +
                      field->row_kind + " = 0).");
    }
    return path;
  }

  // first index: a row by number, or by the name of the object owning the rows
  const std::string& row = parsed.indices[0];
  long row_first = 0, row_count = 1;
  if (field->row_kind.empty()) {
    // options and scalars: a single index selects an element of the vector
    if (parsed.indices.size() > 1) {
      throw PathError("path '" + std::string(text) + "': '" + field->name +
                      "' takes a single index.");
    }
    std::optional<long> k = ParseIndex(row);
    if (!k) {
      throw PathError("path '" + std::string(text) + "': '" + field->name +
                      "' is indexed by number (0.." + std::to_string(path.count - 1) + ").");
    }
    if (*k >= path.count) {
      throw PathError("path '" + std::string(text) + "': index " + row + " is out of bounds; '" +
                      field->name + "' has " + std::to_string(path.count) + " element(s).");
    }
    path.first = *k;
    path.count = 1;
    path.text = canonical + "[" + row + "]";
    return path;
  }
  const RowKind* kind = FindRowKind(field->row_kind);
  if (std::optional<long> index = ParseIndex(row)) {
    if (*index >= rows) {
      throw PathError("path '" + std::string(text) + "': row " + row + " is out of bounds; '" +
                      field->name + "' has " + std::to_string(rows) + " row(s) (" +
                      field->row_kind + " = " + std::to_string(rows) + ").");
    }
    row_first = *index;
  } else {
    if (!kind) {
      throw PathError("path '" + std::string(text) + "': the rows of '" + field->name +
                      "' (counted by " + field->row_kind +
                      ") have no names; use a number from 0 to " + std::to_string(rows - 1) + ".");
    }
    // "#3": the object with id 3 (how '*' names unnamed objects), else a name
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
                      "' (the rows of '" + field->name + "' are " + kind->noun + "s)." + listing);
    }
    auto [first, count] = RowsOf(m, *kind, id);
    if (count == 0) {
      throw PathError("path '" + std::string(text) + "': " + kind->noun + " '" + row +
                      "' has no row in '" + field->name +
                      "' (for example, an actuator without "
                      "activation has no act, a body that is not mocap has no mocap_pos).");
    }
    row_first = first;
    row_count = count;
  }
  path.first = row_first * cols;
  path.count = row_count * cols;
  canonical += "[" + row + "]";

  // second index: an element within the row block
  if (parsed.indices.size() == 2) {
    std::optional<long> k = ParseIndex(parsed.indices[1]);
    if (!k) {
      throw PathError("path '" + std::string(text) + "': the element index '" + parsed.indices[1] +
                      "' must be a number from 0 to " + std::to_string(path.count - 1) + ".");
    }
    if (*k >= path.count) {
      throw PathError("path '" + std::string(text) + "': element " + parsed.indices[1] +
                      " is out of bounds; '" + canonical + "' has " + std::to_string(path.count) +
                      " element(s).");
    }
    path.first += *k;
    path.count = 1;
    canonical += "[" + parsed.indices[1] + "]";
  }
  path.text = canonical;
  return path;
}

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
  if (path.role == Role::kDerived) {
    why =
        "it is derived: MuJoCo computes it from the state (qpos, qvel, act) and inputs "
        "(ctrl) in mj_forward/mj_step; set those instead.";
  } else if (Contains(kConstants, field.name)) {
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

// Throws PathError when element `k` of `path` lies beyond the rows `d` holds now. The
// constraint and contact arrays (efc_*, contact, islands) hold as many rows as the
// state has constraints (nefc), a number that changes from step to step; beyond them
// is nothing MuJoCo computed.
void RequireCurrentRow(const FieldInfo& field, const mjModel* m, const mjData* d, const Path& path,
                       long k) {
  if (!field.current_rows) return;
  long count = field.current_rows(m, d) * field.cols(m);
  if (path.first + k < count) return;
  // 2.x allocates these arrays for njmax/nconmax rows; 3.x counts them by nefc/ncon
  const std::string& kind = field.row_kind;
  std::string now = kind == "njmax" ? "nefc" : kind == "nconmax" ? "ncon" : kind;
  std::string room = now == kind ? "" : "; it has room for " + kind + " = " + std::to_string(field.rows(m)) + " rows";
  throw PathError("'" + path.text + "' does not exist at t = " + FormatNumber(d->time) +
                  " s: there are " + now + " = " + std::to_string(field.current_rows(m, d)) +
                  " rows now ('" + field.name + "' holds " + std::to_string(count) +
                  " element(s)" + room +
                  ", but the constraints and contacts active at this state fill only " + now +
                  " of them, a number that changes with contacts and limits from step to step).");
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

std::vector<Path> ScalarPaths(const Path& path) {
  if (path.count == 1) return {path};
  std::vector<Path> out;
  for (long k = 0; k < path.count; ++k) {
    Path one = path;
    one.first = path.first + k;
    one.count = 1;
    one.text = path.text + "[" + std::to_string(k) + "]";
    out.push_back(one);
  }
  return out;
}

std::vector<Path> DefaultColumns(const Model& model) {
  const mjModel* m = model.get();
  std::vector<Path> columns = {ResolvePath(model, "time")};
  auto add = [&](const std::string& text) {
    for (Path& p : ScalarPaths(ResolvePath(model, text))) columns.push_back(std::move(p));
  };
  for (const char* field : {"qpos", "qvel"}) {
    bool is_qpos = std::string(field) == "qpos";
    for (int j = 0; j < m->njnt; ++j) {
      std::string name = model.Name(mjOBJ_JOINT, j);
      if (!name.empty()) {
        add(std::string(field) + "[" + name + "]");
        continue;
      }
      // unnamed joints: address their raw rows, one per coordinate
      int adr = is_qpos ? m->jnt_qposadr[j] : m->jnt_dofadr[j];
      int n = is_qpos ? JointQposSize(m->jnt_type[j]) : JointDofSize(m->jnt_type[j]);
      for (int k = 0; k < n; ++k) add(std::string(field) + "[" + std::to_string(adr + k) + "]");
    }
  }
  for (int s = 0; s < m->nsensor; ++s) {
    std::string name = model.Name(mjOBJ_SENSOR, s);
    if (name.empty()) {
      // unnamed sensors: address the raw sensordata rows
      for (int k = 0; k < m->sensor_dim[s]; ++k) {
        add("sensordata[" + std::to_string(m->sensor_adr[s] + k) + "]");
      }
    } else {
      add("sensordata[" + name + "]");
    }
  }
  return columns;
}

double ReadValue(const Model& model, const Data& data, const Path& path, long k) {
  const FieldInfo& field = Fields()[path.field_index];
  RequireCurrentRow(field, model.get(), data.get(), path, k);
  const char* at = static_cast<const char*>(FieldBase(field, model.get(), data.get())) +
                   (path.first + k) * ElemSize(field.type);
  switch (field.type) {
    case ElemType::kNum:
      return *reinterpret_cast<const mjtNum*>(at);
    case ElemType::kInt:
      return *reinterpret_cast<const int*>(at);
    case ElemType::kInt64:
      return static_cast<double>(*reinterpret_cast<const long long*>(at));
    case ElemType::kByte:
      return *reinterpret_cast<const mjtByte*>(at);
    case ElemType::kBool:
      return *reinterpret_cast<const bool*>(at) ? 1 : 0;
    case ElemType::kFloat:
      return *reinterpret_cast<const float*>(at);
    case ElemType::kChar:
      return *reinterpret_cast<const char*>(at);
    case ElemType::kOther:
      break;
  }
  return std::numeric_limits<double>::quiet_NaN();
}

void WriteValues(Model& model, Data& data, const Path& path, const std::vector<double>& values) {
  const FieldInfo& field = Fields()[path.field_index];
  RequireWritable(path);
  if (static_cast<long>(values.size()) != path.count) {
    throw ValueError("'" + path.text + "' takes " + std::to_string(path.count) + " value(s), got " +
                     std::to_string(values.size()) + ".");
  }
  for (double v : values) CheckValue(field.type, path.text, v);
  if (path.field == "body_mass") KeepShape(model.get_mutable(), path, values);
  for (long k = 0; k < path.count; ++k) {
    double v = values[k];
    void* at = MutableElement(model, data, path, k);
    switch (field.type) {
      case ElemType::kNum:
        *static_cast<mjtNum*>(at) = v;
        break;
      case ElemType::kFloat:
        *static_cast<float*>(at) = static_cast<float>(v);
        break;
      case ElemType::kInt:
        *static_cast<int*>(at) = static_cast<int>(v);
        break;
      case ElemType::kInt64:
        *static_cast<long long*>(at) = static_cast<long long>(v);
        break;
      case ElemType::kByte:
        *static_cast<mjtByte*>(at) = static_cast<mjtByte>(v);
        break;
      case ElemType::kBool:
        *static_cast<bool*>(at) = v != 0;
        break;
      case ElemType::kChar:
      case ElemType::kOther:
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
  auto fail = [&](const std::string& why) { throw ValueError(text + ": " + why + "."); };
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
    warnings.push_back("--set '" + a.text + "': the orientation quaternion of joint " +
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
    int id = -1;
    for (int u = 0; u < m->nu && id < 0; ++u) {
      if (is_ctrl ? u == row : compat::ActuatorActAddress(m, u) == row) id = u;
    }
    if (id < 0) continue;
    bool limited = is_ctrl ? m->actuator_ctrllimited[id] : m->actuator_actlimited[id];
    if (!limited) continue;
    const mjtNum* range = (is_ctrl ? m->actuator_ctrlrange : m->actuator_actrange) + 2 * id;
    double v = a.values[k];
    if (v >= range[0] && v <= range[1]) continue;
    std::string name = model.Name(mjOBJ_ACTUATOR, id);
    std::string actuator = name.empty() ? "#" + std::to_string(id) : "'" + name + "'";
    double clamped = std::clamp(v, range[0], range[1]);
    warnings.push_back("--set '" + a.text + "': " + FormatNumber(v) + " is outside the " +
                       (is_ctrl ? "ctrlrange" : "actrange") + " [" + FormatNumber(range[0]) + ", " +
                       FormatNumber(range[1]) + "] of actuator " + actuator +
                       "; MuJoCo clamps it, so the actuator acts as if " + a.path.field + " = " +
                       FormatNumber(clamped) + ".");
  }
  return warnings;
}

}  // namespace

Assignment ParseAssignment(const Model& model, std::string_view text) {
  std::size_t eq = text.find('=');
  if (eq == std::string_view::npos) {
    throw ValueError("--set '" + std::string(text) +
                     "': expected PATH=VALUE, e.g. qpos[hinge]=0.7 or opt.gravity=0,0,-1.62.");
  }
  Assignment a;
  a.text = std::string(text);
  a.path = ResolvePath(model, text.substr(0, eq));
  std::string value_text(text.substr(eq + 1));
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
        throw ValueError("--set '" + a.text + "': '" + item + "' is not a valid " + a.path.field +
                         "; valid names: " + Join(valid, ", ") + ".");
      }
    }
    if (!v) {
      throw ValueError("--set '" + a.text + "': '" + item + "' is not a number.");
    }
    if (!std::isfinite(*v)) {
      throw ValueError("--set '" + a.text + "': " + item + " is not a finite number.");
    }
    a.values.push_back(*v);
  }
  if (static_cast<long>(a.values.size()) != a.path.count) {
    throw ValueError("--set '" + a.text + "': '" + a.path.text + "' is " +
                     BlockDescription(model, a.path) + "; give exactly " +
                     std::to_string(a.path.count) + " values separated by commas (got " +
                     std::to_string(a.values.size()) + "), or set one element, e.g. " +
                     a.path.text + "[0]=" + FormatNumber(a.values.front()) + ".");
  }
  RequireWritable(a.path);
  for (double v : a.values) CheckValue(Fields()[a.path.field_index].type, a.text, v);
  CheckDomain(a.path, "--set '" + a.text + "'", a.values);
  a.warnings = SilentChangeWarnings(model, a);
  return a;
}

void CheckAssignable(const Path& path, double value) {
  CheckValue(Fields()[path.field_index].type, path.text, value);
  CheckDomain(path, "'" + path.text + "' = " + FormatNumber(value), {value});
}

void ApplyAssignments(Model& model, Data& data, const std::vector<Assignment>& assignments) {
  // parameters first: the state edits below may depend on them (qpos0, sizes)
  // (inertias the user gives last: they override the rescaling a new mass implies)
  bool arrays_changed = false;
  for (bool inertia : {false, true}) {
    for (const Assignment& a : assignments) {
      if (a.path.role != Role::kParameter || (a.path.field == "body_inertia") != inertia) continue;
      WriteValues(model, data, a.path, a.values);
      if (Fields()[a.path.field_index].source == FieldSource::kModelArray) arrays_changed = true;
    }
  }
  // recompute constants derived from masses, inertias and qpos0 (uses its own data:
  // mj_setConst overwrites the state it is given)
  if (arrays_changed) {
    Data scratch(model);
    mj_setConst(model.get_mutable(), scratch.get());
  }
  data.Reset();
  for (const Assignment& a : assignments) {
    if (a.path.role != Role::kParameter) WriteValues(model, data, a.path, a.values);
  }
  // the chapter's rule: after setting state, make derived quantities consistent
  data.Forward();
}

}  // namespace plumb
