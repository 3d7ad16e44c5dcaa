// Geometry of MuJoCo's primitive geoms that more than one check needs.

#ifndef PLUMB_SRC_CORE_GEOMETRY_H_
#define PLUMB_SRC_CORE_GEOMETRY_H_

#include <mujoco/mujoco.h>

#include <cmath>
#include <limits>

namespace plumb::internal {

// Volume in m^3 of a primitive geom of `type` with compiled `size` (geom_size: radius,
// half-lengths); NaN for planes, meshes, height fields and SDFs, whose volume the
// compiled sizes do not give.
inline double PrimitiveVolume(int type, const mjtNum* size) {
  constexpr double kPi = 3.14159265358979323846;
  switch (type) {
    case mjGEOM_SPHERE:
      return 4.0 / 3 * kPi * size[0] * size[0] * size[0];
    case mjGEOM_CAPSULE:
      return kPi * size[0] * size[0] * 2 * size[1] + 4.0 / 3 * kPi * std::pow(size[0], 3);
    case mjGEOM_CYLINDER:
      return kPi * size[0] * size[0] * 2 * size[1];
    case mjGEOM_BOX:
      return 8 * size[0] * size[1] * size[2];
    case mjGEOM_ELLIPSOID:
      return 4.0 / 3 * kPi * size[0] * size[1] * size[2];
    default:
      return std::numeric_limits<double>::quiet_NaN();
  }
}

// Angle in rad between the directions of two 3-vectors (any lengths), accurate near 0 and pi
// (atan2 of the cross and dot products, where acos of the dot loses half the digits).
inline double AngleBetween(const double* a, const double* b) {
  const double cx = a[1] * b[2] - a[2] * b[1];
  const double cy = a[2] * b[0] - a[0] * b[2];
  const double cz = a[0] * b[1] - a[1] * b[0];
  const double dot = a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
  return std::atan2(std::sqrt(cx * cx + cy * cy + cz * cz), dot);
}

// The rotation angle in rad, in [0, pi], that takes orientation `a` to `b` (quaternions w, x,
// y, z of any length; q and -q are one orientation), accurate for tiny angles.
inline double RotationAngle(const double* a, const double* b) {
  // the relative rotation conj(a) * b: its vector part's length is sin(angle / 2) |a| |b|
  const double w = a[0] * b[0] + a[1] * b[1] + a[2] * b[2] + a[3] * b[3];
  const double x = a[0] * b[1] - a[1] * b[0] - a[2] * b[3] + a[3] * b[2];
  const double y = a[0] * b[2] + a[1] * b[3] - a[2] * b[0] - a[3] * b[1];
  const double z = a[0] * b[3] - a[1] * b[2] + a[2] * b[1] - a[3] * b[0];
  return 2 * std::atan2(std::sqrt(x * x + y * y + z * z), std::abs(w));
}

}  // namespace plumb::internal

#endif  // PLUMB_SRC_CORE_GEOMETRY_H_
