#include "core/geometry.h"

#include <gtest/gtest.h>

#include <cmath>

namespace plumb {
using internal::PrimitiveVolume;

namespace {

// audit's inertia checks and verify's density exercise had a volume function each
TEST(GeometryTest, PrimitiveVolumesAndNoneForMeshes) {
  const mjtNum sphere[3] = {0.5, 0, 0}, box[3] = {1, 2, 3}, capsule[3] = {0.05, 0.5, 0};
  EXPECT_DOUBLE_EQ(PrimitiveVolume(mjGEOM_SPHERE, sphere), 4.0 / 3 * M_PI * 0.125);
  EXPECT_DOUBLE_EQ(PrimitiveVolume(mjGEOM_BOX, box), 48);
  // the chapter's pendulum rod: a cylinder 1 m long and two half-spheres
  EXPECT_DOUBLE_EQ(PrimitiveVolume(mjGEOM_CAPSULE, capsule),
                   M_PI * 0.0025 * 1 + 4.0 / 3 * M_PI * 0.000125);
  EXPECT_TRUE(std::isnan(PrimitiveVolume(mjGEOM_MESH, box)));
  EXPECT_TRUE(std::isnan(PrimitiveVolume(mjGEOM_PLANE, box)));
}

}  // namespace
}  // namespace plumb
