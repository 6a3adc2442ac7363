#include "virtual_tryon/core/drape/pattern_transform.h"
#include "virtual_tryon/core/geometry/rigid_transform.h"
#include "virtual_tryon/core/io/report_summary.h"
#include "virtual_tryon/core/scenes/procedural.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include <string>
#include <vector>

using namespace virtual_tryon;

TEST(ReportSummary, ResolveSummaryConvergedAndNot) {
  ResolverReport r;
  r.converged = true;
  r.garment_edge_crossings_before = 12;
  r.body_edge_crossings_before = 3;
  r.iterations = 4;
  r.moved_vertices = 57;
  r.max_displacement = 0.0123;
  r.clearance = 0.002;
  r.seconds_total = 0.052;
  EXPECT_EQ(resolveSummary(r),
            "resolved 12 garment-edge + 3 body-edge crossings in 4 iterations (57 vertices moved, max "
            "0.0123 m, clearance 0.002 m) in 0.052 s");
  r.clearance = 0.0042;
  r.body_uncertainty = 0.0022;  // a scanned body's error
  EXPECT_EQ(resolveSummary(r),
            "resolved 12 garment-edge + 3 body-edge crossings in 4 iterations (57 vertices moved, max "
            "0.0123 m, clearance 0.0042 m, of which 0.0022 m the body's uncertainty) in 0.052 s");
  r.converged = false;
  r.iterations = 50;
  r.reason = "stalled";
  r.garment_edge_crossings_after = 2;
  r.body_edge_crossings_after = 0;
  EXPECT_EQ(resolveSummary(r),
            "not converged after 50 iterations: stalled (2 garment-edge + 0 body-edge crossings left)");
}

TEST(ReportSummary, InputWarningsAndTheirSuffix) {
  const TriMesh body = makeSphere(0.3);
  TriMesh garment = makeSphere(0.35);
  EXPECT_TRUE(inputWarnings({}, body, garment, MeshLimits()).empty());
  EXPECT_EQ(warningSuffix({}), "");

  garment.V.rowwise() += Eigen::RowVector3d(10, 0, 0);  // far away
  garment.F.conservativeResize(garment.F.rows() + 1, 3);
  garment.F.row(garment.F.rows() - 1) << 0, 0, 1;  // degenerate
  const std::vector<std::string> w = inputWarnings({"body has 2 separate pieces"}, body, garment, MeshLimits());
  ASSERT_EQ(w.size(), 3u);
  EXPECT_EQ(w[0], "body has 2 separate pieces");
  EXPECT_EQ(w[1], "garment has 1 degenerate face (a repeated vertex or zero area)");
  EXPECT_EQ(w[2].rfind("garment is ", 0), 0u) << w[2];
  EXPECT_EQ(warningSuffix({"a", "b"}), "; warning: a; warning: b");
}

TEST(ReportSummary, DrapeMessage) {
  DrapeResult r;
  r.success = true;
  r.message = "draped";
  r.warnings = {"seam 1 open"};
  r.map_size = 512;
  EXPECT_EQ(drapeMessage(r, {"body is open"}, CollisionMode::ImageSpace, true),
            "draped; warning: body is open; warning: seam 1 open; depth maps rendered (512 px)");
  EXPECT_EQ(drapeMessage(r, {}, CollisionMode::ImageSpace, false),
            "draped; warning: seam 1 open; depth maps reused (cached with the body)");
  EXPECT_EQ(drapeMessage(r, {}, CollisionMode::ObjectSpace, true), "draped; warning: seam 1 open");
  r.success = false;
  r.message = "blew up";
  EXPECT_EQ(drapeMessage(r, {"w"}, CollisionMode::ImageSpace, true), "blew up; warning: w; warning: seam 1 open");
}

TEST(RigidTransform, MeshVerticesAndPanelPosesMove) {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = Eigen::AngleAxisd(0.7, Eigen::Vector3d(0, 1, 1).normalized()).toRotationMatrix();
  T.translation() = Eigen::Vector3d(0.5, -1, 2);

  const TriMesh sphere = makeSphere(0.3);
  TriMesh moved = sphere;
  transformMesh(T, moved);
  ASSERT_EQ(moved.V.rows(), sphere.V.rows());
  EXPECT_TRUE(moved.F == sphere.F);
  for (Eigen::Index i = 0; i < sphere.V.rows(); ++i)
    EXPECT_LT((Eigen::Vector3d(moved.V.row(i)) - T * Eigen::Vector3d(sphere.V.row(i))).norm(), 1e-15);

  Pattern p;
  p.panels.resize(2);
  p.panels[1].placement.pose.translation() = Eigen::Vector3d(0, 1, 0);
  p.panels[1].placement.wrap_radius = 0.2;
  transformPattern(T, p);
  EXPECT_TRUE(p.panels[0].placement.pose.isApprox(T));
  EXPECT_LT((p.panels[1].placement.pose.translation() - T * Eigen::Vector3d(0, 1, 0)).norm(), 1e-15);
  EXPECT_EQ(p.panels[1].placement.wrap_radius, 0.2);
}
