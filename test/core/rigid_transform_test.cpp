// Rigid motions: the z-up world pose of a y-up body (REP 103), for rviz.
#include "virtual_tryon/core/geometry/rigid_transform.h"
#include "virtual_tryon/core/scenes/procedural.h"

#include <gtest/gtest.h>

using namespace virtual_tryon;

TEST(RigidTransform, AYUpBodyStandsOnTheZUpWorldsFloor) {
  // A capsule standing along +y from y = -0.8 (MakeHuman's feet) with its front at +z.
  TriMesh body = makeCapsule(0.15, 1.3, Eigen::Vector3d(0, -0.8 + 0.15 + 0.65, 0));
  const Eigen::Isometry3d T = zUpWorldFromBody(body, Eigen::Vector3d::UnitY());
  EXPECT_TRUE((T.linear() * Eigen::Vector3d::UnitY()).isApprox(Eigen::Vector3d::UnitZ(), 1e-12));
  EXPECT_NEAR(T.linear().determinant(), 1.0, 1e-12);  // a rotation, not a mirror
  // Its front (+z in the mesh) faces -y in the world, a right-handed turn about x.
  EXPECT_TRUE((T.linear() * Eigen::Vector3d::UnitZ()).isApprox(-Eigen::Vector3d::UnitY(), 1e-12));
  transformMesh(T, body);
  EXPECT_NEAR(body.V.col(2).minCoeff(), 0.0, 1e-12);  // on the floor
  EXPECT_NEAR(body.V.col(2).maxCoeff(), 1.6, 1e-9);    // standing, its height along +z
  // Already z-up: only the lift.
  const Eigen::Isometry3d I = zUpWorldFromBody(makeSphere(0.5, Eigen::Vector3d(0, 0, 2)), Eigen::Vector3d::UnitZ());
  EXPECT_TRUE(I.linear().isIdentity(1e-12));
  EXPECT_NEAR(I.translation().z(), -1.5, 1e-9);
  EXPECT_TRUE(zUpWorldFromBody(TriMesh(), Eigen::Vector3d::UnitX()).translation().isZero());
}
