// The solid a body's geoms describe, filled at a uniform density: its volume, centroid,
// second moments and extent in the body frame, meshes included (from mesh_vert/mesh_face:
// mjModel keeps no mesh volume). The inertia checks hold a body's compiled mass, centre of
// mass and inertia against it. Private to the audit (src/audit/).

#ifndef PLUMB_SRC_AUDIT_BODY_SHAPE_H_
#define PLUMB_SRC_AUDIT_BODY_SHAPE_H_

#include <mujoco/mujoco.h>

#include <array>
#include <string>

namespace plumb::audit {

struct Solid {
  double volume = 0;                 // m^3
  std::array<double, 3> centroid{};  // m, body frame
  // the second moment about the centroid, integral of (x - c)(x - c)^T dV (m^5), body frame
  std::array<double, 9> second{};
  std::array<double, 3> lo{}, hi{};  // the box of the body frame that holds every vertex
  bool approximate = false;          // a mesh that is not closed, taken as its box
  int geoms = 0;
  int meshes = 0;  // of them, meshes

  // Principal moments (ascending, kg*m^2) of the inertia this solid has at `mass`.
  std::array<double, 3> PrincipalMoments(double mass) const;
  // How far `point` lies outside the box (0 inside), m.
  double OutsideBox(const mjtNum* point) const;
  // Half the box's diagonal, m.
  double HalfDiagonal() const;
};

// How a row names a solid: "its 3 geoms (2 meshes)", ", open meshes taken as their boxes" added
// when it is approximate.
std::string ShapeWords(const Solid& shape);

// The solid of geom g in its body's frame; volume 0 for planes, height fields and SDFs.
Solid GeomSolid(const mjModel* m, int g);

// The solids of body b's geoms, computed once: `shape`, the geoms that describe its shape (the
// visual geoms, contype and conaffinity 0, when they hold more volume than the colliding ones:
// a robot's visual meshes are its links, its collision geoms often a few spheres at the feet;
// else the colliding ones), and `all`, every geom with a volume (where the body has matter).
// Volumes 0 when the body has no geom with a volume.
struct BodySolids {
  Solid shape, all;
  Solid visual, colliding;  // the two sets `shape` was chosen from
  int meshes = 0;  // mesh geoms of the body
};
BodySolids BodySolid(const mjModel* m, int b);

}  // namespace plumb::audit

#endif  // PLUMB_SRC_AUDIT_BODY_SHAPE_H_
