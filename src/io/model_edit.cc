// Writing a model with changed parameters through mjSpec (plumb/model_edit.h).

#include "plumb/model_edit.h"

#include <fmt/format.h>

#include <cstring>
#include <filesystem>
#include <limits>
#include <memory>

#include "core/fields.h"
#include "core/mujoco_compat.h"
#include "io/atomic_file.h"
#include "plumb/error.h"

namespace plumb {
using internal::AtomicFile;
using internal::FieldInfo;
using internal::Fields;

#if PLUMB_MUJOCO_HAS_SPEC

namespace {

struct SpecDeleter {
  void operator()(mjSpec* s) const { mj_deleteSpec(s); }
};
using SpecPtr = std::unique_ptr<mjSpec, SpecDeleter>;

// The spec's element of MuJoCo object `type` for the model's row `id`, found by name.
mjsElement* Element(mjSpec* spec, const Model& model, int type, int id, const Path& path) {
  std::string name = model.Name(type, id);
  if (name.empty()) {
    throw ValueError(
        fmt::format("-o: {} belongs to an element without a name; name it in the "
                    "MJCF to save the fitted value",
                    path.text));
  }
  mjsElement* e = mjs_findElement(spec, static_cast<mjtObj>(type), name.c_str());
  if (e == nullptr) {
    throw ValueError(
        fmt::format("-o: the MJCF has no {} '{}' for {}", mju_type2Str(type), name, path.text));
  }
  return e;
}

// Sets the value the model holds at `path` on its element in `spec`.
void SetOnSpec(mjSpec* spec, const Model& model, const Path& path) {
  const mjModel* m = model.get();
  const FieldInfo& field = Fields()[path.field_index];
  long cols = field.cols(m);
  int row = static_cast<int>(path.first / cols);
  int col = static_cast<int>(path.first % cols);
  const std::string& f = path.field;
  if (f == "dof_damping" || f == "dof_armature" || f == "dof_frictionloss") {
    mjsJoint* j = mjs_asJoint(Element(spec, model, mjOBJ_JOINT, m->dof_jntid[row], path));
    if (f == "dof_damping") j->damping[0] = m->dof_damping[row];
    if (f == "dof_armature") j->armature = m->dof_armature[row];
    if (f == "dof_frictionloss") j->frictionloss = m->dof_frictionloss[row];
  } else if (f == "jnt_stiffness") {
    mjs_asJoint(Element(spec, model, mjOBJ_JOINT, row, path))->stiffness[0] = m->jnt_stiffness[row];
  } else if (f == "body_mass" || f == "body_ipos" || f == "body_inertia") {
    // the whole inertial, explicit: a mass set alone would be recomputed from the geoms
    mjsBody* b = mjs_asBody(Element(spec, model, mjOBJ_BODY, row, path));
    b->explicitinertial = 1;
    b->mass = m->body_mass[row];
    for (int k = 0; k < 3; ++k) b->ipos[k] = m->body_ipos[3 * row + k];
    for (int k = 0; k < 4; ++k) b->iquat[k] = m->body_iquat[4 * row + k];
    for (int k = 0; k < 3; ++k) b->inertia[k] = m->body_inertia[3 * row + k];
    for (double& v : b->fullinertia) v = std::numeric_limits<double>::quiet_NaN();
    b->ialt.type = mjORIENTATION_QUAT;
  } else if (f == "geom_friction") {
    mjs_asGeom(Element(spec, model, mjOBJ_GEOM, row, path))->friction[col] =
        m->geom_friction[3 * row + col];
  } else if (f == "actuator_gear" || f == "actuator_gainprm" || f == "actuator_biasprm") {
    mjsActuator* a = mjs_asActuator(Element(spec, model, mjOBJ_ACTUATOR, row, path));
    if (f == "actuator_gear") a->gear[col] = m->actuator_gear[6 * row + col];
    if (f == "actuator_gainprm") a->gainprm[col] = m->actuator_gainprm[mjNGAIN * row + col];
    if (f == "actuator_biasprm") a->biasprm[col] = m->actuator_biasprm[mjNBIAS * row + col];
  } else {
    throw ValueError(fmt::format(
        "-o cannot write {} yet (it writes dof_damping, dof_armature, dof_frictionloss, "
        "jnt_stiffness, body_mass, body_ipos, body_inertia, geom_friction, actuator_gear, "
        "actuator_gainprm, actuator_biasprm)",
        path.text));
  }
}

// Makes a relative asset folder absolute, resolved against the source's folder.
void AbsoluteFolder(mjString* folder, const std::filesystem::path& base) {
  std::string now = mjs_getString(folder);
  if (now.empty() || std::filesystem::path(now).is_absolute()) return;
  mjs_setString(folder, (base / now).lexically_normal().string().c_str());
}

// What differs between two compiled models' elements (sizes, then names), or "".
std::string ElementDifference(const mjModel* a, const mjModel* b) {
  const std::pair<const char*, int> sizes[] = {{"nq", a->nq - b->nq},
                                               {"nv", a->nv - b->nv},
                                               {"nu", a->nu - b->nu},
                                               {"nbody", a->nbody - b->nbody},
                                               {"njnt", a->njnt - b->njnt},
                                               {"ngeom", a->ngeom - b->ngeom},
                                               {"nsite", a->nsite - b->nsite},
                                               {"nsensor", a->nsensor - b->nsensor},
                                               {"nnames", a->nnames - b->nnames}};
  for (const auto& [name, difference] : sizes) {
    if (difference != 0) return fmt::format("its {} differs by {}", name, difference);
  }
  if (a->nnames > 0 && std::memcmp(a->names, b->names, a->nnames) != 0) {
    return "its elements have other names";
  }
  return "";
}

}  // namespace

bool CanSaveEditedXml() { return true; }

std::string SourceMismatch(const std::string& source, const Model& model) {
  char error[1024] = "";
  SpecPtr spec(mj_parseXML(source.c_str(), nullptr, error, sizeof error));
  if (!spec) return fmt::format("it does not parse: {}", error);
  mjModel* compiled = mj_compile(spec.get(), nullptr);
  if (compiled == nullptr) return fmt::format("it does not compile: {}", mjs_getError(spec.get()));
  std::string difference = ElementDifference(compiled, model.get());
  mj_deleteModel(compiled);
  return difference;
}

void SaveXmlWithParameters(const std::string& source_xml, const Model& edited,
                           const std::vector<Path>& paths, const std::string& out) {
  char error[1024] = "";
  SpecPtr spec(mj_parseXML(source_xml.c_str(), nullptr, error, sizeof error));
  if (!spec) throw LoadError(fmt::format("{}: {}", source_xml, error), "");
  for (const Path& path : paths) SetOnSpec(spec.get(), edited, path);
  namespace fs = std::filesystem;
  fs::path source_dir = fs::absolute(source_xml).parent_path();
  if (fs::absolute(out).parent_path() != source_dir) {
    AbsoluteFolder(spec->compiler.meshdir, source_dir);
    AbsoluteFolder(spec->compiler.texturedir, source_dir);
  }
  mjModel* check = mj_compile(spec.get(), nullptr);
  if (check == nullptr) {
    throw LoadError(fmt::format("{} with the fitted values does not compile: {}", source_xml,
                                mjs_getError(spec.get())),
                    "");
  }
  std::string difference = ElementDifference(check, edited.get());
  mj_deleteModel(check);
  if (!difference.empty()) {
    throw ValueError(
        fmt::format("{} is not the MJCF of the fitted model {} ({}): give the file "
                    "that model was compiled from",
                    source_xml, edited.file(), difference));
  }
  int size = mj_saveXMLString(spec.get(), nullptr, 0, error, sizeof error);
  std::string xml(size > 0 ? size + 1 : 0, '\0');
  if (size <= 0 || mj_saveXMLString(spec.get(), xml.data(), size + 1, error, sizeof error) != 0) {
    throw IoError(fmt::format("cannot write the fitted model {}: {}", out, error));
  }
  xml.resize(size);
  AtomicFile file(out);
  std::fwrite(xml.data(), 1, xml.size(), file.stream());
  file.Commit();
}

#else  // no mjSpec

bool CanSaveEditedXml() { return false; }

std::string SourceMismatch(const std::string&, const Model&) {
  return fmt::format("MuJoCo {} cannot parse MJCF apart from compiling it", mj_versionString());
}

void SaveXmlWithParameters(const std::string&, const Model&, const std::vector<Path>&,
                           const std::string& out) {
  throw UnavailableError(fmt::format(
      "-o {}: writing a fitted model needs MuJoCo's model-editing API (mjSpec, MuJoCo 3.10 or "
      "later); this plumb is built with MuJoCo {}. Build with the default MuJoCo, or set the "
      "fitted values in the MJCF by hand",
      out, mj_versionString()));
}

#endif

}  // namespace plumb
