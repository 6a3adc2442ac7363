// The vertex push-out baseline: inside vertices go to the surface plus the margin; it tests no
// edge, so crossings may remain (which is what the evaluation shows).
#include "virtual_tryon/testing/push_out_baseline.h"
#include "virtual_tryon/core/scenes/procedural.h"
#include "virtual_tryon/testing/reference_bvh.h"

#include <gtest/gtest.h>

using namespace virtual_tryon;
using V3 = Eigen::Vector3d;

TEST(PushOutBaseline, InsideVerticesGoToTheSurfacePlusTheMargin) {
  const TriMesh sphere = makeSphere(0.1, V3::Zero(), 4);
  TriMesh garment = makePatch(0.12, 0.12, 24, 24, V3(0.003, 0.08, -0.002));
  const TriMesh before = garment;
  ReferenceReferee ref(sphere);
  const ReferenceCounts c0 = ref.count(garment);
  ASSERT_GT(c0.vertices_inside, 20u);
  Body b(sphere);
  PushOutParams p;
  p.margin = 0.002;
  const PushOutReport rep = pushOutBaseline(b, garment, p);
  EXPECT_EQ(rep.vertices_inside, c0.vertices_inside);
  EXPECT_GT(rep.max_displacement, 0.005);
  const ReferenceCounts c1 = ref.count(garment);
  EXPECT_EQ(c1.vertices_inside, 0u);
  // Every moved vertex sits at the margin from the surface (nearest point + margin * face normal).
  std::size_t moved = 0;
  for (Eigen::Index v = 0; v < garment.V.rows(); ++v) {
    if ((garment.V.row(v) - before.V.row(v)).norm() == 0) continue;
    ++moved;
    ReferenceTree t(sphere);
    EXPECT_NEAR(t.distance(sphere, garment.V.row(v).transpose()), 0.002, 1e-9);
  }
  EXPECT_EQ(moved, rep.vertices_inside);
}

TEST(PushOutBaseline, LeavesEdgeCrossingsAVertexTestCannotSee) {
  // A thin finger through the middle of one big triangle: no garment vertex is inside, so the
  // baseline moves nothing and the finger still pierces the face.
  const TriMesh finger = makeCylinder(0.01, 0.2, V3::Zero(), 16, 3, true);
  TriMesh garment = makePatch(0.3, 0.3, 2, 2, V3(0.031, 0.0, -0.047));
  Body b(finger);
  const PushOutReport rep = pushOutBaseline(b, garment);
  EXPECT_EQ(rep.vertices_inside, 0u);
  EXPECT_GT(ReferenceReferee(finger).count(garment).body_edge_crossings, 0u);
}

TEST(PushOutBaseline, OpenBodyUsesTheSideOfTheNearestFace) {
  const TriMesh tube = makeCylinder(0.1, 0.4, V3::Zero(), 32, 8, false);
  TriMesh patch = makePatch(0.03, 0.03, 6, 6, V3(0.07, 0.0, 0.0));  // inside the tube
  Body b(tube);
  ASSERT_FALSE(b.closed());
  const PushOutReport rep = pushOutBaseline(b, patch);
  EXPECT_FALSE(rep.body_closed);
  EXPECT_EQ(rep.vertices_inside, static_cast<std::size_t>(patch.V.rows()));
  for (Eigen::Index v = 0; v < patch.V.rows(); ++v)
    EXPECT_GT(std::hypot(patch.V(v, 0), patch.V(v, 2)), 0.095);
}
