// Reading paths at a sample: the value an element holds now (refusing constraint rows
// beyond the ones the state fills), and the columns a log records by default. Resolving
// the names is path.cc; writing values is path_values.cc.

#include <limits>
#include <string>
#include <vector>

#include "core/fields.h"
#include "core/joint_size.h"
#include "core/strings.h"
#include "plumb/error.h"
#include "plumb/path.h"

namespace plumb {
using internal::ElemSize;
using internal::FieldBase;
using internal::FieldInfo;
using internal::Fields;
using internal::FormatNumber;
using internal::JointDofSize;
using internal::JointQposSize;
using internal::ReadElement;

namespace {

using compat::ElemType;

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
  std::string room =
      now == kind ? ""
                  : "; it has room for " + kind + " = " + std::to_string(field.rows(m)) + " rows";
  throw PathError("'" + path.text + "' does not exist at t = " + FormatNumber(d->time) +
                  " s: there are " + now + " = " + std::to_string(field.current_rows(m, d)) +
                  " rows now ('" + field.name + "' holds " + std::to_string(count) + " element(s)" +
                  room + ", but the constraints and contacts active at this state fill only " +
                  now +
                  " of them, a number that changes with contacts and limits from step to step).");
}

}  // namespace

std::vector<Path> ScalarPaths(const Path& path) {
  if (path.count == 1) return {path};
  if (path.count > kMostScalarPaths) {
    // a constraint array sized by MuJoCo's arena holds millions of rows: as many paths would
    // take gigabytes (found by the fuzzer: 'efc_AR_rownnz' on the humanoid)
    throw PathError("'" + path.text + "' holds " + std::to_string(path.count) +
                    " elements, too many to take one by one (at most " +
                    std::to_string(kMostScalarPaths) + "): name the rows you want, e.g. '" +
                    path.text + "[0]'.");
  }
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
  // the inputs, so a log of the run carries what drove it (replay reads them back)
  for (int u = 0; u < compat::ActuatorCount(m); ++u) {
    std::string name = model.Name(mjOBJ_ACTUATOR, u);
    if (!name.empty()) {
      add("ctrl[" + name + "]");
      continue;
    }
    auto [first, count] = compat::ActuatorControls(m, u);
    for (long k = 0; k < count; ++k) add("ctrl[" + std::to_string(first + k) + "]");
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
  if (path.bit >= 0) {
    Path whole = path;
    whole.bit = -1;
    return (static_cast<long long>(ReadValue(model, data, whole, k)) >> path.bit) & 1;
  }
  RequireCurrentRow(field, model.get(), data.get(), path, k);
  const char* at = static_cast<const char*>(FieldBase(field, model.get(), data.get())) +
                   (path.first + k) * ElemSize(field.type);
  return ReadElement(field.type, at);
}

}  // namespace plumb
