// Writing a model with changed parameters back to MJCF, every attribute right.
//
// mj_saveLastXML writes the model as it was compiled and cannot express every runtime edit
// (an edited body_mass is lost: the body's inertial came from its geoms). This goes through
// MuJoCo's model-editing API (mjSpec): the source MJCF is parsed again, each changed value is
// set on its element (a joint's damping, a body's explicit inertial, a geom's friction, an
// actuator's gear, ...), the result is compiled to check it and saved.
//
// Example:
//   plumb::SaveXmlWithParameters("arm.xml", fitted, {ResolvePath(fitted, "body_mass[payload]")},
//                                "arm-fitted.xml");
//
// Thread-safety: SaveXmlWithParameters keeps no state of its own and only reads `edited`; it
// parses the source into an mjSpec of its own, not through MuJoCo's global "last XML" that
// Model::Load serialises, and writes `out` through AtomicFile (see atomic_file.h).

#ifndef PLUMB_INCLUDE_PLUMB_MODEL_EDIT_H_
#define PLUMB_INCLUDE_PLUMB_MODEL_EDIT_H_

#include <string>
#include <vector>

#include "plumb/model.h"
#include "plumb/path.h"

namespace plumb {

// Whether this build can write edited models (MuJoCo 3.10 or later: mjSpec).
bool CanSaveEditedXml();

// Why the MJCF file `source` is not the MJCF of `model`: it does not parse or compile
// (reading its files relative to its own folder), or it has other elements (sizes, names).
// "" when it is. Before MuJoCo 3.10 (no mjSpec) always a reason.
std::string SourceMismatch(const std::string& source, const Model& model);

// Writes `source_xml` with the values `edited` holds at `paths` to `out` (whole or not at
// all). `source_xml` must compile to `edited`'s elements (SourceMismatch). Supported fields: dof_damping, dof_armature, dof_frictionloss, jnt_stiffness,
// body_mass, body_ipos, body_inertia, geom_friction, actuator_gear, actuator_gainprm,
// actuator_biasprm. Relative mesh and texture folders are made absolute when `out` lies in
// another folder.
// @throws UnavailableError before MuJoCo 3.10; ValueError for an unsupported field, an
// element without a name or a source of other elements; LoadError when the source does not
// parse or the edited model does not compile; IoError when `out` cannot be written.
void SaveXmlWithParameters(const std::string& source_xml, const Model& edited,
                           const std::vector<Path>& paths, const std::string& out);

}  // namespace plumb

#endif  // PLUMB_INCLUDE_PLUMB_MODEL_EDIT_H_
