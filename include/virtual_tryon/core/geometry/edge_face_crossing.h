// The exact-as-doubles-allow predicate at the heart of discrete collision detection: does a segment
// cross a triangle? Stateless, no allocation.
//
// Conventions
// - sa, sb: signed distances of the segment's end-points a, b from the triangle's plane, positive
//   on the side the normal (p1 - p0) x (p2 - p0) points to.
// - The segment crosses the plane when the end-points are on strictly opposite sides, or when one
//   lies on the plane and the other strictly behind it (sa == 0, sb < 0): touching the front of a
//   face is legal, leaving through it is not. Both on the plane (coplanar) is not a crossing.
// - The crossing point must lie in the closed triangle. The test uses the signed volumes of the
//   segment with each triangle edge; each volume is evaluated with the edge's end-points in a
//   canonical (lexicographic) order and negated as needed, so two triangles that share an edge
//   get exactly opposite values for it: a segment through a shared edge or vertex is never missed
//   by both (watertight), though it may be reported by both.
#pragma once

#include <Eigen/Core>

namespace virtual_tryon {

struct EdgeFaceHit {
  double sa = 0, sb = 0;        // signed distances of a and b from the plane (unit normal)
  double t = 0;                 // crossing point = a + t (b - a), t in [0, 1]
  Eigen::Vector3d bary{0, 0, 0};  // barycentric coordinates of the crossing point in (p0, p1, p2)
};

// True when segment [a, b] crosses triangle (p0, p1, p2) by the conventions above; fills `hit`.
// A degenerate (zero-area) triangle or a zero-length segment never crosses.
bool segmentCrossesTriangle(const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                            const Eigen::Vector3d& p0, const Eigen::Vector3d& p1,
                            const Eigen::Vector3d& p2, EdgeFaceHit* hit = nullptr);

}  // namespace virtual_tryon
