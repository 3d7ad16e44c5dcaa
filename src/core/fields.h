// The table of every mjModel, mjOption and mjData field reachable through a path,
// generated from MuJoCo's X-macros so it follows the MuJoCo version plumb is built with.

#ifndef PLUMB_SRC_CORE_FIELDS_H_
#define PLUMB_SRC_CORE_FIELDS_H_

#include <mujoco/mujoco.h>

#include <string>
#include <string_view>
#include <vector>

#include "core/mujoco_compat.h"

namespace plumb::internal {

enum class FieldSource {
  kModelArray,  // pointer field of mjModel
  kModelSize,   // int size field of mjModel (nq, nv, ...), read-only
  kOption,      // field of mjModel::opt
  kDataArray,   // pointer field of mjData
  kDataScalar,  // time and other scalar/vector fields stored inline in mjData
};

struct FieldInfo {
  std::string name;  // as users type it: "qpos", "body_mass", "opt.gravity", "time"
  FieldSource source;
  compat::ElemType type;
  std::size_t offset;    // byte offset within mjModel, mjOption or mjData
  std::string row_kind;  // mjModel size naming the rows ("nbody", "nq", ...); "" if none
  long (*rows)(const mjModel*);  // rows allocated (for constraint arrays: the most they hold)
  long (*cols)(const mjModel*);
  // For arrays whose filled row count changes from step to step (constraints, contacts,
  // islands): the rows holding values at the state of `d`; nullptr for every other field.
  long (*current_rows)(const mjModel*, const mjData*) = nullptr;
};

// Every field, in X-macro order: model arrays, model sizes, options, data arrays,
// data scalars.
const std::vector<FieldInfo>& Fields();

// The field called `name`, or nullptr.
const FieldInfo* FindField(std::string_view name);

// Address of element 0 of the field in `m`/`d` (d may be null for model fields).
const void* FieldBase(const FieldInfo& field, const mjModel* m, const mjData* d);

// Size in bytes of one element.
std::size_t ElemSize(compat::ElemType type);

// The element of `type` at `at` as a double (a char's code; NaN for kOther).
double ReadElement(compat::ElemType type, const void* at);

// Writes `value` into the element of `type` at `at`, converted to the type (it does not check
// the value fits: see WriteValues). Returns false, writing nothing, for kChar and kOther.
bool WriteElement(compat::ElemType type, void* at, double value);

}  // namespace plumb::internal

#endif  // PLUMB_SRC_CORE_FIELDS_H_
