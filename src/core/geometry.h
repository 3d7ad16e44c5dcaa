// Geometry of MuJoCo's primitive geoms that more than one check needs.

#ifndef PLUMB_SRC_CORE_GEOMETRY_H_
#define PLUMB_SRC_CORE_GEOMETRY_H_

#include <mujoco/mujoco.h>

#include <cmath>
#include <limits>

namespace plumb {

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

}  // namespace plumb

#endif  // PLUMB_SRC_CORE_GEOMETRY_H_
