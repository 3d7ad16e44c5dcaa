// Audit layer 2, inertia.density: the density a moving weld group's mass implies in the volume
// of its bodies' shapes, and where the MJCF is at hand, the density each geom's written `mass`
// implies in its own volume. No solid is lighter than air or heavier than osmium.

#include <fmt/format.h>

#include <algorithm>
#include <string>
#include <vector>

#include "audit/audit_layers.h"
#include "audit/body_shape.h"

namespace plumb::audit {
namespace {

constexpr const char* L = "inertia";
constexpr int kNamedBodies = 4;  // welded bodies a group's row names before "and N more"

// The densities a solid may have, kg/m^3: 1 .. 25000 for primitives (no solid is lighter than
// air or heavier than osmium), 10 .. 1e5 when a mesh is part of the shape, since a mesh often
// shows part of a link while its motor hides in the parent's mesh (Mini Cheetah's hips: 28600);
// a mesh in mm is still 1e9 off.
struct Band {
  double lo, hi;
};
Band DensityBand(bool mesh) { return mesh ? Band{10, 1e5} : Band{1, 25000}; }

// How far `density` lies outside `band`: 0 inside, +1 above it, -1 below it.
int Outside(double density, Band band) {
  return density > band.hi ? 1 : density < band.lo ? -1 : 0;
}

// A geom whose written mass, in its own volume, lies outside its band.
struct WrongGeom {
  int g;
  double mass, volume, density;
  Band band;
  int side;  // Outside()
};

// A moving weld group: its root (not welded to its parent), the bodies welded to it, and what
// they hold together.
struct Group {
  std::vector<int> bodies;  // the root first
  double mass = 0, volume = 0;
  bool approximate = false;  // an open mesh in some body's shape, taken as its box
  int meshes = 0;
  int heaviest = -1;
};

Group ReadGroup(const mjModel* m, int root, const std::vector<BodySolids>& shapes) {
  Group group;
  for (int b = root; b < m->nbody; ++b) {
    if (m->body_weldid[b] != root) continue;
    const BodySolids& solids = shapes[b];
    group.bodies.push_back(b);
    group.mass += m->body_mass[b];
    group.volume += solids.shape.volume;
    group.approximate = group.approximate || solids.shape.approximate;
    group.meshes += solids.meshes;
    if (group.heaviest < 0 || m->body_mass[b] > m->body_mass[group.heaviest]) group.heaviest = b;
  }
  return group;
}

// The geoms of the group's bodies that carry a written mass (`geom_masses`) the compiler used
// (their body's inertia derived from its geoms, `written` false) and whose density in their own
// closed volume lies outside their band (the mesh band for mesh geoms). A mass of 0 is a geom
// left out of the body's mass on purpose, not judged.
std::vector<WrongGeom> WrongGeoms(const mjModel* m, const Group& group,
                                  const std::vector<double>& geom_masses,
                                  const std::vector<bool>& written) {
  std::vector<WrongGeom> out;
  for (int b : group.bodies) {
    if (written[b]) continue;
    for (int g = m->body_geomadr[b]; g < m->body_geomadr[b] + m->body_geomnum[b]; ++g) {
      const double mass = geom_masses[g];
      if (!(mass > 0)) continue;
      const Solid solid = GeomSolid(m, g);
      if (!(solid.volume > 0) || solid.approximate) continue;
      const Band band = DensityBand(m->geom_type[g] == mjGEOM_MESH);
      const double density = mass / solid.volume;
      const int side = Outside(density, band);
      if (side != 0) out.push_back({g, mass, solid.volume, density, band, side});
    }
  }
  return out;
}

std::string Quoted(const Model& model, int b) {
  const std::string name = model.Name(mjOBJ_BODY, b);
  return name.empty() ? fmt::format("#{}", b) : "'" + name + "'";
}

// geom 'pad' (id 7) writes mass="20" kg, 4.49e+05 kg/m^3 in its 4.46e-05 m^3
std::string GeomWords(const Model& model, const WrongGeom& geom) {
  return fmt::format("{} writes mass=\"{:g}\" kg, {:.3g} kg/m^3 in its {:.3g} m^3",
                     Elem(model, mjOBJ_GEOM, geom.g, "geom"), geom.mass, geom.density, geom.volume);
}

// The group's row. A group of one body reads as the single-body row always did; a group of
// several names its welded bodies, and the one that carries most of the mass when that is not
// the root. Geoms whose written mass errs the same way are named in the fix, not in rows of
// their own: one cause, one row.
void GroupRow(const Model& model, const Group& group, const std::vector<WrongGeom>& geoms,
              std::vector<CheckRow>* out) {
  const mjModel* m = model.get();
  const int root = group.bodies.front();
  const Band band = DensityBand(group.meshes > 0);
  const double density = group.mass / group.volume;
  std::string measured =
      fmt::format("{:.4g} kg/m^3 ({:.4g} kg in {:.3g} m^3)", density, group.mass, group.volume);
  std::string fix =
      "no solid is this light or heavy (water 1000, steel 7850): check the mass, the geom sizes "
      "and their units (a mesh in mm is 1e9 times too big)";
  const int welded = static_cast<int>(group.bodies.size()) - 1;
  if (welded > 0) {
    std::string names;
    for (int k = 1; k <= std::min(welded, kNamedBodies); ++k) {
      names += (k > 1 ? ", " : "") + Quoted(model, group.bodies[k]);
    }
    if (welded > kNamedBodies) names += fmt::format(" and {} more", welded - kNamedBodies);
    measured += fmt::format(" for the weld group of {} and {} welded bod{} ({})",
                            Quoted(model, root), welded, welded == 1 ? "y" : "ies", names);
    if (group.heaviest != root) {
      measured += fmt::format("; welded {} carries {:.4g} kg of it", Quoted(model, group.heaviest),
                              m->body_mass[group.heaviest]);
    }
    fix += fmt::format(
        ". The group moves as one body: which of its bodies carries the mass is arbitrary, its "
        "total is not. Check the masses of {}{}",
        Quoted(model, group.heaviest), group.heaviest == root ? "" : " first");
  }
  for (const WrongGeom& geom : geoms) {
    fix += "; " + GeomWords(model, geom) + ": check that mass and the geom's size, and their units";
  }
  // a body with nothing welded to it and no written mass to name keeps the row it always had
  if (welded > 0 || !geoms.empty()) {
    fix += "; a mass lumped there on purpose: declare it in the accept list, with the reason";
  }
  out->push_back(WithNumbers(
      Make(L, "inertia.density", ElementOf(model, mjOBJ_BODY, root, "body"), measured,
           fmt::format("{:g} .. {:g} kg/m^3", band.lo, band.hi), CheckStatus::kWarn, fix),
      {density, "kg/m^3"}, {density < band.lo ? band.lo : band.hi, "kg/m^3"}));
}

// A geom's own row: its written mass is no material's in its volume, while its group passes
// (the mass hides in the group's total), errs the other way, or is not judged.
void GeomRow(const Model& model, const WrongGeom& geom, std::vector<CheckRow>* out) {
  const int b = model.get()->geom_bodyid[geom.g];
  out->push_back(WithNumbers(
      Make(L, "inertia.density", ElementOf(model, mjOBJ_GEOM, geom.g, "geom"),
           fmt::format("{:.4g} kg/m^3 (mass=\"{:g}\" kg written, in its {:.3g} m^3) in {}",
                       geom.density, geom.mass, geom.volume, Elem(model, mjOBJ_BODY, b, "body")),
           fmt::format("{:g} .. {:g} kg/m^3", geom.band.lo, geom.band.hi), CheckStatus::kWarn,
           fmt::format("no solid is this light or heavy (water 1000, steel 7850): check the "
                       "geom's mass attribute and its unit (grams written as kg are 1000 times "
                       "too heavy), and its size; {:.3g} kg is water in this volume, {:.3g} kg "
                       "steel. A mass lumped there on purpose: declare it in the accept list",
                       1000 * geom.volume, 7850 * geom.volume)),
      {geom.density, "kg/m^3"}, {geom.side < 0 ? geom.band.lo : geom.band.hi, "kg/m^3"}));
}

}  // namespace

void WeldGroupDensity(const Model& model, int b, const std::vector<BodySolids>& shapes,
                      const std::vector<double>* geom_masses, const std::vector<bool>* written,
                      std::vector<CheckRow>* out) {
  const mjModel* m = model.get();
  if (m->body_weldid[b] != b) return;
  const Group group = ReadGroup(m, b, shapes);
  std::vector<WrongGeom> geoms;
  if (geom_masses && written) geoms = WrongGeoms(m, group, *geom_masses, *written);
  int side = 0;
  if (group.volume > 0 && !group.approximate && group.mass > 0) {
    side = Outside(group.mass / group.volume, DensityBand(group.meshes > 0));
  }
  // a geom that errs the way its group does is that row's cause: named there
  std::vector<WrongGeom> cause, own;
  for (const WrongGeom& geom : geoms)
    (side != 0 && geom.side == side ? cause : own).push_back(geom);
  if (side != 0) GroupRow(model, group, cause, out);
  for (const WrongGeom& geom : own) GeomRow(model, geom, out);
}

}  // namespace plumb::audit
