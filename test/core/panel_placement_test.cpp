// Panel placement: a pattern panel's (u, v) into 3D, flat in its pose's x-y plane or wrapped
// round a cylinder about the pose's y axis.
#include "pattern_helpers.h"
#include "virtual_tryon/core/drape/pattern.h"

#include <gtest/gtest.h>

#include <cmath>

using namespace virtual_tryon;
using namespace virtual_tryon_test;

TEST(PanelPlacement, FlatMapsIntoThePosesXYPlane) {
  PanelPlacement pl;
  EXPECT_TRUE(pl.place(Eigen::Vector2d(0.3, -0.2)).isApprox(Eigen::Vector3d(0.3, -0.2, 0)));
  pl.pose.translation() = Eigen::Vector3d(1, 2, 3);
  pl.pose.linear() = Eigen::AngleAxisd(kPi / 2, Eigen::Vector3d::UnitY()).toRotationMatrix();
  // u along the pose's x (world -z after a quarter turn about y), v along y.
  EXPECT_LT((pl.place(Eigen::Vector2d(0.5, 0.25)) - Eigen::Vector3d(1, 2.25, 2.5)).norm(), 1e-12);
}

TEST(PanelPlacement, WrapPutsNodesOnTheCylinder) {
  PanelPlacement pl;
  pl.wrap_radius = 0.2;
  pl.pose.translation() = Eigen::Vector3d(0.1, 0.9, -0.05);
  // u = 0 is on the pose's +z side.
  EXPECT_LT((pl.place(Eigen::Vector2d(0, 0.3)) - Eigen::Vector3d(0.1, 1.2, 0.15)).norm(), 1e-12);
  // A quarter turn of arc length reaches the +x side.
  EXPECT_LT((pl.place(Eigen::Vector2d(kPi * 0.2 / 2, 0)) - Eigen::Vector3d(0.3, 0.9, -0.05)).norm(), 1e-12);
  for (double u = -0.6; u <= 0.6; u += 0.05) {
    const Eigen::Vector3d p = pl.place(Eigen::Vector2d(u, 0.4)) - pl.pose.translation();
    EXPECT_NEAR(std::hypot(p.x(), p.z()), 0.2, 1e-12) << "u = " << u;
    EXPECT_NEAR(p.y(), 0.4, 1e-12);
  }
}
