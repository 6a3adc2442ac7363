// Degenerate-case sweeps for the segment-triangle predicate (ipc-toolkit style).
#include "virtual_tryon/core/geometry/edge_face_crossing.h"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

using virtual_tryon::EdgeFaceHit;
using virtual_tryon::segmentCrossesTriangle;
using V3 = Eigen::Vector3d;

namespace {
const V3 p0(0, 0, 0), p1(1, 0, 0), p2(0, 1, 0);  // normal +z
}

TEST(EdgeFaceCrossing, ThroughInteriorGivesPointAndWeights) {
  EdgeFaceHit hit;
  ASSERT_TRUE(segmentCrossesTriangle(V3(0.2, 0.3, -1), V3(0.2, 0.3, 3), p0, p1, p2, &hit));
  EXPECT_NEAR(hit.t, 0.25, 1e-15);
  EXPECT_NEAR(hit.sa, -1, 1e-15);
  EXPECT_NEAR(hit.sb, 3, 1e-15);
  EXPECT_NEAR(hit.bary[0], 0.5, 1e-15);
  EXPECT_NEAR(hit.bary[1], 0.2, 1e-15);
  EXPECT_NEAR(hit.bary[2], 0.3, 1e-15);
  // Either direction crosses.
  EXPECT_TRUE(segmentCrossesTriangle(V3(0.2, 0.3, 3), V3(0.2, 0.3, -1), p0, p1, p2));
}

TEST(EdgeFaceCrossing, MissesAndSameSide) {
  EXPECT_FALSE(segmentCrossesTriangle(V3(0.8, 0.8, -1), V3(0.8, 0.8, 1), p0, p1, p2));  // outside
  EXPECT_FALSE(segmentCrossesTriangle(V3(0.2, 0.2, 0.1), V3(0.2, 0.2, 1), p0, p1, p2));  // in front
  EXPECT_FALSE(segmentCrossesTriangle(V3(0.2, 0.2, -0.1), V3(0.2, 0.2, -1), p0, p1, p2));  // behind
  EXPECT_FALSE(segmentCrossesTriangle(V3(0.2, 0.2, -1), V3(0.2, 0.2, -1), p0, p1, p2));  // zero length
  EXPECT_FALSE(segmentCrossesTriangle(V3(0.2, 0.2, -1), V3(0.2, 0.2, 1), p0, p1, V3(2, 0, 0)));  // degenerate
}

TEST(EdgeFaceCrossing, CoplanarIsNotACrossing) {
  EXPECT_FALSE(segmentCrossesTriangle(V3(-1, 0.2, 0), V3(2, 0.2, 0), p0, p1, p2));
  EXPECT_FALSE(segmentCrossesTriangle(V3(0.1, 0.1, 0), V3(0.2, 0.2, 0), p0, p1, p2));
}

TEST(EdgeFaceCrossing, TouchingFromTheFrontIsLegalLeavingThroughTheBackIsNot) {
  // One end-point exactly on the face.
  EXPECT_FALSE(segmentCrossesTriangle(V3(0.2, 0.2, 0), V3(0.2, 0.2, 1), p0, p1, p2));
  EXPECT_FALSE(segmentCrossesTriangle(V3(0.2, 0.2, 1), V3(0.2, 0.2, 0), p0, p1, p2));
  EdgeFaceHit hit;
  ASSERT_TRUE(segmentCrossesTriangle(V3(0.2, 0.2, 0), V3(0.2, 0.2, -1), p0, p1, p2, &hit));
  EXPECT_EQ(hit.t, 0.0);
  EXPECT_TRUE(segmentCrossesTriangle(V3(0.2, 0.2, -1), V3(0.2, 0.2, 0), p0, p1, p2));
}

// A fan of triangles round a vertex, and segments through that vertex and along the fan's edges,
// then shifted by tiny offsets: the fan as a whole must never miss the segment (watertight), and
// only a triangle that holds the crossing point may report it: near spoke `target` the two
// triangles on either side of it (a point on the spoke may be reported by both), near the centre
// any of them (they all hold it), each at the point where the segment meets the fan.
TEST(EdgeFaceCrossing, WatertightThroughSharedVertexAndEdgesWithTinyOffsets) {
  const V3 c(0.3, -0.2, 0.1);
  const int n = 7;
  std::vector<V3> ring;
  for (int i = 0; i < n; ++i) {
    const double a = 2 * M_PI * i / n + 0.1;
    ring.push_back(c + V3(std::cos(a), std::sin(a), 0.05 * std::sin(3 * a)));
  }
  const std::vector<double> offsets = {0.0, 1e-12, -1e-12, 1e-15, -1e-15, 1e-9, -1e-9};
  for (int target = 0; target <= n; ++target) {
    // target == n: through the centre vertex; otherwise through the midpoint of spoke `target`
    // (c, ring[target]), the edge of triangles target - 1 and target (triangle i is c, ring[i],
    // ring[i + 1]).
    const V3 base = target == n ? c : V3(c + 0.5 * (ring[target] - c));
    for (double ox : offsets)
      for (double oy : offsets) {
        SCOPED_TRACE(::testing::Message() << "target " << target << " offsets " << ox << " " << oy);
        const V3 q = base + V3(ox, oy, 0);
        const V3 a = q + V3(0.01, 0.02, -1), b = q + V3(-0.01, -0.02, 1);
        int hits = 0;
        for (int i = 0; i < n; ++i) {
          const V3 &t0 = c, &t1 = ring[i], &t2 = ring[(i + 1) % n];
          EdgeFaceHit hit;
          if (!segmentCrossesTriangle(a, b, t0, t1, t2, &hit)) continue;
          ++hits;
          if (target < n) {
            EXPECT_TRUE(i == target || i == (target + n - 1) % n)
                << "triangle " << i << " does not touch spoke " << target;
          }
          // The crossing is reported where it is: the same point by the segment's parameter and
          // by the triangle's weights, within a few offsets of q (the fan is flat to first order
          // there, and the segment steep).
          const V3 onSegment = a + hit.t * (b - a);
          const V3 onTriangle = hit.bary[0] * t0 + hit.bary[1] * t1 + hit.bary[2] * t2;
          EXPECT_LT((onSegment - onTriangle).norm(), 1e-9) << "triangle " << i;
          EXPECT_LT((onSegment - q).norm(), 1e-8) << "triangle " << i;
        }
        EXPECT_GE(hits, 1);
      }
  }
}

TEST(EdgeFaceCrossing, ThroughAnEdgeOfTwoTrianglesCountsAtLeastOnce) {
  // Two triangles sharing the edge (0,0,0)-(1,1,0), in either winding of the shared edge.
  const V3 a(0, 0, 0), b(1, 1, 0), c1(1, 0, 0), c2(0, 1, 0);
  for (double off : {0.0, 1e-12, -1e-12, 1e-16, -1e-16}) {
    const V3 q(0.5 + off, 0.5 - off, 0);
    const bool below = segmentCrossesTriangle(q + V3(0, 0, -1), q + V3(0, 0, 1), a, c1, b);  // x > y
    const bool above = segmentCrossesTriangle(q + V3(0, 0, -1), q + V3(0, 0, 1), a, b, c2);  // x < y
    EXPECT_GE(below + above, 1) << off;
    // Exactly on the shared edge (off = 0) the point is in both closed triangles and both report
    // it; off it, only the triangle it is in (x > y for off > 0), however small the offset.
    EXPECT_EQ(below, off >= 0) << off;
    EXPECT_EQ(above, off <= 0) << off;
  }
}

TEST(EdgeFaceCrossing, TinyOffsetsAcrossTheBoundaryAreDecidedConsistently) {
  // Segment near the triangle's outer edge x + y = 1 at offsets of 1e-12: inside -> hit.
  for (double off : {1e-6, 1e-9, 1e-12}) {
    EXPECT_TRUE(segmentCrossesTriangle(V3(0.5 - off, 0.5 - off, -1), V3(0.5 - off, 0.5 - off, 1), p0, p1, p2));
    EXPECT_FALSE(segmentCrossesTriangle(V3(0.5 + off, 0.5 + off, -1), V3(0.5 + off, 0.5 + off, 1), p0, p1, p2));
  }
  // End-point a hair behind the plane.
  EdgeFaceHit hit;
  ASSERT_TRUE(segmentCrossesTriangle(V3(0.2, 0.2, -1e-12), V3(0.2, 0.2, 1), p0, p1, p2, &hit));
  EXPECT_NEAR(hit.sa, -1e-12, 1e-24);
  EXPECT_FALSE(segmentCrossesTriangle(V3(0.2, 0.2, 1e-12), V3(0.2, 0.2, 1), p0, p1, p2));
}
