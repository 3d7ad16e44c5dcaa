// What an MJCF says beyond the model it compiles to, read with mjSpec (MuJoCo 3.10+): which
// inertias were written, which geoms write a mass, which default class gives each element its
// solref. Each reader aligns the parsed elements with the compiled ones by id and returns
// nullopt (or an empty kind) when that fails, on 2.x (no mjSpec) and for a binary model. Part
// of src/core/mujoco_compat.h, which includes it: include that header, never this one.

#ifndef PLUMB_SRC_CORE_MUJOCO_COMPAT_SPEC_H_
#define PLUMB_SRC_CORE_MUJOCO_COMPAT_SPEC_H_

#include <mujoco/mujoco.h>

#include <cstring>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#ifndef PLUMB_MUJOCO_HAS_SPEC
#error "include core/mujoco_compat.h, not core/mujoco_compat_spec.h"
#endif

namespace plumb::compat {

namespace detail {
#if PLUMB_MUJOCO_HAS_SPEC
struct SpecDeleter {
  void operator()(mjSpec* spec) const { mj_deleteSpec(spec); }
};
// The mjSpec of the MJCF text `xml`, else of the file `path`; null when it does not parse.
inline std::unique_ptr<mjSpec, SpecDeleter> ParseSpec(const std::string& xml,
                                                      const std::string& path) {
  char error[500] = "";
  return std::unique_ptr<mjSpec, SpecDeleter>(
      xml.empty() ? mj_parseXML(path.c_str(), nullptr, error, sizeof(error))
                  : mj_parseXMLString(xml.c_str(), nullptr, error, sizeof(error)));
}
#endif
}  // namespace detail

// Per body id, whether its mass and inertia were written in an <inertial> element (true) or
// derived by the compiler from its geoms (false), read with mjSpec from the MJCF text `xml`,
// else from the file `path`. nullopt when that cannot be told: MuJoCo 2.x has no mjSpec, a
// binary model has no source, or the parsed bodies do not line up with the compiled ones.
inline std::optional<std::vector<bool>> ExplicitInertials(const std::string& xml,
                                                          const std::string& path,
                                                          const mjModel* m) {
#if PLUMB_MUJOCO_HAS_SPEC
  auto parsed = detail::ParseSpec(xml, path);
  mjSpec* spec = parsed.get();
  if (!spec) return std::nullopt;
  std::vector<bool> out;
  bool aligned = true;
  for (mjsElement* e = mjs_firstElement(spec, mjOBJ_BODY); e; e = mjs_nextElement(spec, e)) {
    int id = static_cast<int>(out.size());
    const char* name = mjs_getString(mjs_getName(e));
    const char* compiled = id < m->nbody ? mj_id2name(m, mjOBJ_BODY, id) : nullptr;
    if (id >= m->nbody || (name && *name && (!compiled || std::strcmp(name, compiled) != 0))) {
      aligned = false;
      break;
    }
    bool explicit_inertial = mjs_asBody(e)->explicitinertial;
    if (spec->compiler.inertiafromgeom == mjINERTIAFROMGEOM_TRUE) explicit_inertial = false;
    out.push_back(explicit_inertial);
  }
  if (!aligned || static_cast<int>(out.size()) != m->nbody) return std::nullopt;
  return out;
#else
  (void)xml;
  (void)path;
  (void)m;
  return std::nullopt;
#endif
}

// Per geom id, the mass (kg) its MJCF writes in a `mass` attribute (its own or its default
// class's), read with mjSpec from the MJCF text `xml`, else from the file `path`: mjsGeom::mass
// is NaN unless written (MuJoCo's user code defaults it so on 3.x and 4.x). NaN too for a geom
// whose mass spreads over its surface (shellinertia, or its mesh's inertia="shell"), which has
// no volume to hold it. nullopt when that cannot be told: MuJoCo 2.x has no mjSpec, a binary
// model has no source, or the parsed geoms do not line up with the compiled ones (by count, and
// by the geom's and its body's names where named).
inline std::optional<std::vector<double>> WrittenGeomMasses(
    [[maybe_unused]] const std::string& xml, [[maybe_unused]] const std::string& path,
    [[maybe_unused]] const mjModel* m) {
#if PLUMB_MUJOCO_HAS_SPEC
  auto spec = detail::ParseSpec(xml, path);
  if (!spec) return std::nullopt;
  auto same = [](const char* written, const char* compiled) {
    return !written || !*written || (compiled && std::strcmp(written, compiled) == 0);
  };
  std::vector<double> out;
  for (mjsElement* e = mjs_firstElement(spec.get(), mjOBJ_GEOM); e;
       e = mjs_nextElement(spec.get(), e)) {
    const int g = static_cast<int>(out.size());
    mjsBody* body = mjs_getParent(e);
    if (g >= m->ngeom || !same(mjs_getString(mjs_getName(e)), mj_id2name(m, mjOBJ_GEOM, g)) ||
        !body ||
        !same(mjs_getString(mjs_getName(body->element)),
              mj_id2name(m, mjOBJ_BODY, m->geom_bodyid[g]))) {
      return std::nullopt;
    }
    const mjsGeom* geom = mjs_asGeom(e);
    bool shell = geom->typeinertia == mjINERTIA_SHELL;
    const char* mesh = mjs_getString(geom->meshname);
    mjsElement* asset = mesh && *mesh ? mjs_findElement(spec.get(), mjOBJ_MESH, mesh) : nullptr;
    if (asset) shell = shell || mjs_asMesh(asset)->inertia == mjMESH_INERTIA_SHELL;
    out.push_back(shell ? NAN : geom->mass);
  }
  if (static_cast<int>(out.size()) == m->ngeom) return out;
#endif
  return std::nullopt;
}

// The default class an element takes its solref attributes from, as its MJCF says: the class's
// name ("main" for the top-level default) and the time constants (solref[0]) that class gives
// each solref attribute of the element's kind, in the order of ClampedSolrefArrays' arrays of
// that kind: geom {solref}, joint {solreflimit, solreffriction}, tendon {solreflimit,
// solreffriction}, equality {solref}, pair {solref, solreffriction}.
struct SolrefClass {
  std::string name;
  double timeconst[2] = {0, 0};
};

// Per compiled id, for geoms, joints, tendons, equalities and pairs, each element's SolrefClass,
// read with mjSpec from the MJCF text `xml`, else from the file `path`. A kind whose parsed
// elements do not line up with the compiled ones (by count and by name where named) is left
// empty, and everything is nullopt when the source cannot be parsed or on 2.x (no mjSpec).
struct SolrefClasses {
  std::vector<SolrefClass> geom, joint, tendon, equality, pair;
};

namespace detail {
#if PLUMB_MUJOCO_HAS_SPEC
// The SolrefClass of every parsed element of `type`, or empty when they do not line up with
// the compiled model's.
template <class Read>
std::vector<SolrefClass> SpecClasses(mjSpec* spec, const mjModel* m, mjtObj type, int count,
                                     Read read) {
  std::vector<SolrefClass> out;
  for (mjsElement* e = mjs_firstElement(spec, type); e; e = mjs_nextElement(spec, e)) {
    int id = static_cast<int>(out.size());
    const char* name = mjs_getString(mjs_getName(e));
    const char* compiled = id < count ? mj_id2name(m, type, id) : nullptr;
    if (id >= count || (name && *name && (!compiled || std::strcmp(name, compiled) != 0))) {
      return {};
    }
    SolrefClass c;
    const mjsDefault* def = mjs_getDefault(e);
    if (def) {
      const char* class_name = mjs_getString(mjs_getName(def->element));
      c.name = class_name ? class_name : "";
      read(def, c.timeconst);
    }
    out.push_back(c);
  }
  if (static_cast<int>(out.size()) != count) return {};
  return out;
}
#endif
}  // namespace detail

inline std::optional<SolrefClasses> SolrefDefaultClasses([[maybe_unused]] const std::string& xml,
                                                         [[maybe_unused]] const std::string& path,
                                                         [[maybe_unused]] const mjModel* m) {
  std::optional<SolrefClasses> out;
#if PLUMB_MUJOCO_HAS_SPEC
  auto parsed = detail::ParseSpec(xml, path);
  mjSpec* spec = parsed.get();
  if (!spec) return out;
  out.emplace();
  out->geom = detail::SpecClasses(spec, m, mjOBJ_GEOM, m->ngeom, [](const mjsDefault* d, double* t) {
    t[0] = d->geom->solref[0];
  });
  out->joint = detail::SpecClasses(spec, m, mjOBJ_JOINT, m->njnt,
                                   [](const mjsDefault* d, double* t) {
                                     t[0] = d->joint->solref_limit[0];
                                     t[1] = d->joint->solref_friction[0];
                                   });
  out->tendon = detail::SpecClasses(spec, m, mjOBJ_TENDON, m->ntendon,
                                    [](const mjsDefault* d, double* t) {
                                      t[0] = d->tendon->solref_limit[0];
                                      t[1] = d->tendon->solref_friction[0];
                                    });
  out->equality = detail::SpecClasses(spec, m, mjOBJ_EQUALITY, m->neq,
                                      [](const mjsDefault* d, double* t) {
                                        t[0] = d->equality->solref[0];
                                      });
  out->pair = detail::SpecClasses(spec, m, mjOBJ_PAIR, m->npair, [](const mjsDefault* d, double* t) {
    t[0] = d->pair->solref[0];
    t[1] = d->pair->solreffriction[0];
  });
#endif
  return out;
}

}  // namespace plumb::compat

#endif  // PLUMB_SRC_CORE_MUJOCO_COMPAT_SPEC_H_
