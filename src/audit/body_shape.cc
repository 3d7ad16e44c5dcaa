// The solid a body's geoms describe: primitives from their sizes, meshes from their
// triangles (the divergence theorem over signed tetrahedra), combined by the parallel-axis
// theorem in the body frame.

#include "audit/body_shape.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "core/geometry.h"

namespace plumb::audit {
using internal::PrimitiveVolume;

namespace {

using Vec = std::array<double, 3>;
using Mat = std::array<double, 9>;

// Volume, first and second moments (about the origin) of the solid a triangle mesh bounds,
// seen from `origin` (the sums of the signed tetrahedra origin-a-b-c).
struct MeshMoments {
  double volume = 0;
  Vec first{};
  Mat second{};
};

MeshMoments Moments(const mjModel* m, int mesh, const Vec& origin) {
  MeshMoments out;
  const float* vert = m->mesh_vert + 3 * m->mesh_vertadr[mesh];
  const int* face = m->mesh_face + 3 * m->mesh_faceadr[mesh];
  for (int f = 0; f < m->mesh_facenum[mesh]; ++f) {
    Vec v[3];
    for (int k = 0; k < 3; ++k) {
      for (int i = 0; i < 3; ++i) v[k][i] = vert[3 * face[3 * f + k] + i] - origin[i];
    }
    const Vec &a = v[0], &b = v[1], &c = v[2];
    double det = a[0] * (b[1] * c[2] - b[2] * c[1]) - a[1] * (b[0] * c[2] - b[2] * c[0]) +
                 a[2] * (b[0] * c[1] - b[1] * c[0]);
    out.volume += det / 6;
    Vec sum{a[0] + b[0] + c[0], a[1] + b[1] + c[1], a[2] + b[2] + c[2]};
    for (int i = 0; i < 3; ++i) {
      out.first[i] += det / 24 * sum[i];
      for (int j = 0; j < 3; ++j) {
        out.second[3 * i + j] +=
            det / 120 * (a[i] * a[j] + b[i] * b[j] + c[i] * c[j] + sum[i] * sum[j]);
      }
    }
  }
  return out;
}

// A solid box of half-sizes h centred at c (mesh frame): the fallback for open meshes.
void BoxMoments(const Vec& h, double* volume, Mat* second) {
  *volume = 8 * h[0] * h[1] * h[2];
  second->fill(0);
  for (int i = 0; i < 3; ++i) (*second)[4 * i] = *volume * h[i] * h[i] / 3;
}

// A mesh's volume, centroid and central second moment in its own (mesh) frame, and its box.
void MeshSolid(const mjModel* m, int mesh, Solid* s, Vec* centroid) {
  const float* vert = m->mesh_vert + 3 * m->mesh_vertadr[mesh];
  Vec lo{INFINITY, INFINITY, INFINITY}, hi{-INFINITY, -INFINITY, -INFINITY};
  for (int v = 0; v < m->mesh_vertnum[mesh]; ++v) {
    for (int i = 0; i < 3; ++i) {
      lo[i] = std::min(lo[i], static_cast<double>(vert[3 * v + i]));
      hi[i] = std::max(hi[i], static_cast<double>(vert[3 * v + i]));
    }
  }
  s->lo = lo;
  s->hi = hi;
  MeshMoments a = Moments(m, mesh, Vec{0, 0, 0});
  // a closed surface bounds the same volume seen from anywhere; an open one does not
  MeshMoments b = Moments(m, mesh, lo);
  double box = (hi[0] - lo[0]) * (hi[1] - lo[1]) * (hi[2] - lo[2]);
  double sign = a.volume < 0 ? -1 : 1;  // faces wound inside out
  bool closed = std::fabs(a.volume - b.volume) <= 1e-6 * box && std::fabs(a.volume) > 1e-6 * box &&
                std::fabs(a.volume) <= 1.001 * box;
  if (!closed) {
    s->approximate = true;
    Vec h{(hi[0] - lo[0]) / 2, (hi[1] - lo[1]) / 2, (hi[2] - lo[2]) / 2};
    BoxMoments(h, &s->volume, &s->second);
    for (int i = 0; i < 3; ++i) (*centroid)[i] = (lo[i] + hi[i]) / 2;
    return;
  }
  s->volume = sign * a.volume;
  for (int i = 0; i < 3; ++i) (*centroid)[i] = a.first[i] / a.volume;
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) {
      s->second[3 * i + j] =
          sign * a.second[3 * i + j] - s->volume * (*centroid)[i] * (*centroid)[j];
    }
  }
}

// A primitive's central second moment in its own frame (diagonal), with its box.
void PrimitiveSolid(int type, const mjtNum* size, Solid* s) {
  s->volume = PrimitiveVolume(type, size);
  if (std::isnan(s->volume)) {
    s->volume = 0;
    return;
  }
  double r = size[0], V = s->volume;
  Vec diag{}, half{};
  switch (type) {
    case mjGEOM_SPHERE:
      diag = {V * r * r / 5, V * r * r / 5, V * r * r / 5};
      half = {r, r, r};
      break;
    case mjGEOM_ELLIPSOID:
      diag = {V * r * r / 5, V * size[1] * size[1] / 5, V * size[2] * size[2] / 5};
      half = {r, size[1], size[2]};
      break;
    case mjGEOM_BOX:
      diag = {V * r * r / 3, V * size[1] * size[1] / 3, V * size[2] * size[2] / 3};
      half = {r, size[1], size[2]};
      break;
    case mjGEOM_CYLINDER:
      diag = {V * r * r / 4, V * r * r / 4, V * size[1] * size[1] / 3};
      half = {r, r, size[1]};
      break;
    case mjGEOM_CAPSULE: {
      // the cylinder, and the two hemispherical caps (a sphere split at z = +-h)
      double h = size[1];
      double cylinder = M_PI * r * r * 2 * h, caps = 4.0 / 3 * M_PI * r * r * r;
      double across = cylinder * r * r / 4 + caps * r * r / 5;
      diag = {across, across, cylinder * h * h / 3 + caps * (h * h + 0.75 * h * r + r * r / 5)};
      half = {r, r, h + r};
      break;
    }
    default:
      break;
  }
  s->second.fill(0);
  for (int i = 0; i < 3; ++i) {
    s->second[4 * i] = diag[i];
    s->lo[i] = -half[i];
    s->hi[i] = half[i];
  }
}

// Adds `part` (already in the body frame) to `sum` by the parallel-axis theorem.
void Add(const Solid& part, Solid* sum) {
  if (!(part.volume > 0)) return;
  double total = sum->volume + part.volume;
  Vec c;
  for (int i = 0; i < 3; ++i) {
    c[i] = (sum->volume * sum->centroid[i] + part.volume * part.centroid[i]) / total;
  }
  Mat second{};
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) {
      double ds_i = sum->centroid[i] - c[i], ds_j = sum->centroid[j] - c[j];
      double dp_i = part.centroid[i] - c[i], dp_j = part.centroid[j] - c[j];
      second[3 * i + j] = sum->second[3 * i + j] + sum->volume * ds_i * ds_j +
                          part.second[3 * i + j] + part.volume * dp_i * dp_j;
    }
  }
  if (sum->geoms == 0) {
    sum->lo = part.lo;
    sum->hi = part.hi;
  }
  for (int i = 0; i < 3; ++i) {
    sum->lo[i] = std::min(sum->lo[i], part.lo[i]);
    sum->hi[i] = std::max(sum->hi[i], part.hi[i]);
  }
  sum->volume = total;
  sum->centroid = c;
  sum->second = second;
  sum->approximate = sum->approximate || part.approximate;
  sum->geoms += part.geoms;
  sum->meshes += part.meshes;
}

}  // namespace

std::array<double, 3> Solid::PrincipalMoments(double mass) const {
  std::array<double, 3> out{0, 0, 0};
  if (!(volume > 0)) return out;
  double trace = second[0] + second[4] + second[8];
  mjtNum inertia[9], value[3], vector[9], quat[4];
  for (int i = 0; i < 9; ++i) {
    inertia[i] = mass / volume * ((i % 4 == 0 ? trace : 0) - second[i]);
  }
  mju_eig3(value, vector, quat, inertia);
  for (int i = 0; i < 3; ++i) out[i] = value[i];
  std::sort(out.begin(), out.end());
  return out;
}

double Solid::OutsideBox(const mjtNum* point) const {
  double squared = 0;
  for (int i = 0; i < 3; ++i) {
    double d = std::max({lo[i] - point[i], 0.0, point[i] - hi[i]});
    squared += d * d;
  }
  return std::sqrt(squared);
}

double Solid::HalfDiagonal() const {
  return 0.5 * std::sqrt(std::pow(hi[0] - lo[0], 2) + std::pow(hi[1] - lo[1], 2) +
                         std::pow(hi[2] - lo[2], 2));
}

Solid GeomSolid(const mjModel* m, int g) {
  Solid local;
  Vec c{0, 0, 0};
  int type = m->geom_type[g];
  if (type == mjGEOM_MESH && m->geom_dataid[g] >= 0) {
    MeshSolid(m, m->geom_dataid[g], &local, &c);
  } else {
    PrimitiveSolid(type, m->geom_size + 3 * g, &local);
  }
  Solid out;
  if (!(local.volume > 0)) return out;
  // into the body frame: x_body = pos + R x_geom
  mjtNum R[9];
  mju_quat2Mat(R, m->geom_quat + 4 * g);
  const mjtNum* pos = m->geom_pos + 3 * g;
  out.volume = local.volume;
  out.approximate = local.approximate;
  out.geoms = 1;
  out.meshes = type == mjGEOM_MESH;
  for (int i = 0; i < 3; ++i) {
    out.centroid[i] = pos[i] + R[3 * i] * c[0] + R[3 * i + 1] * c[1] + R[3 * i + 2] * c[2];
  }
  // S_body = R S R^T
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) {
      double v = 0;
      for (int k = 0; k < 3; ++k) {
        for (int l = 0; l < 3; ++l) v += R[3 * i + k] * local.second[3 * k + l] * R[3 * j + l];
      }
      out.second[3 * i + j] = v;
    }
  }
  // the body-frame box of the rotated local box
  for (int i = 0; i < 3; ++i) {
    double mid = pos[i], extent = 0;
    for (int k = 0; k < 3; ++k) {
      mid += R[3 * i + k] * (local.lo[k] + local.hi[k]) / 2;
      extent += std::fabs(R[3 * i + k]) * (local.hi[k] - local.lo[k]) / 2;
    }
    out.lo[i] = mid - extent;
    out.hi[i] = mid + extent;
  }
  return out;
}

BodySolids BodySolid(const mjModel* m, int b) {
  BodySolids out;
  Solid &visual = out.visual, &colliding = out.colliding;
  for (int g = m->body_geomadr[b]; g < m->body_geomadr[b] + m->body_geomnum[b]; ++g) {
    bool collides = m->geom_contype[g] != 0 || m->geom_conaffinity[g] != 0;
    Solid part = GeomSolid(m, g);
    Add(part, collides ? &colliding : &visual);
    Add(part, &out.all);
    out.meshes += m->geom_type[g] == mjGEOM_MESH;
  }
  out.shape = visual.volume > colliding.volume ? visual : colliding;
  return out;
}

std::string ShapeWords(const Solid& shape) {
  return fmt::format("its {} geom{}{}{}", shape.geoms, shape.geoms == 1 ? "" : "s",
                     shape.meshes ? fmt::format(" ({} mesh{})", shape.meshes,
                                                shape.meshes == 1 ? "" : "es")
                                  : "",
                     shape.approximate ? ", open meshes taken as their boxes" : "");
}

}  // namespace plumb::audit
