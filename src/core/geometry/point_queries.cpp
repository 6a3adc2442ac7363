#include "virtual_tryon/core/geometry/point_queries.h"

#include "virtual_tryon/core/geometry/edge_face_crossing.h"
#include "core/geometry/body_bvh.h"

#include <algorithm>
#include <vector>

namespace virtual_tryon {

// Ericson, Real-Time Collision Detection, 5.1.5.
Eigen::Vector3d closestPointOnTriangle(const Eigen::Vector3d& p, const Eigen::Vector3d& a,
                                       const Eigen::Vector3d& b, const Eigen::Vector3d& c) {
  const Eigen::Vector3d ab = b - a, ac = c - a, ap = p - a;
  const double d1 = ab.dot(ap), d2 = ac.dot(ap);
  if (d1 <= 0 && d2 <= 0) return a;
  const Eigen::Vector3d bp = p - b;
  const double d3 = ab.dot(bp), d4 = ac.dot(bp);
  if (d3 >= 0 && d4 <= d3) return b;
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0) return a + (d1 / (d1 - d3)) * ab;
  const Eigen::Vector3d cp = p - c;
  const double d5 = ab.dot(cp), d6 = ac.dot(cp);
  if (d6 >= 0 && d5 <= d6) return c;
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0) return a + (d2 / (d2 - d6)) * ac;
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0)
    return b + ((d4 - d3) / ((d4 - d3) + (d5 - d6))) * (c - b);
  const double denom = 1.0 / (va + vb + vc);
  return a + ab * (vb * denom) + ac * (vc * denom);
}

// Through the body's box tree (branch and bound on box distances, exact point-triangle distances
// at the leaves): several times cheaper than FCL's OBBRSS distance query with GJK.
ClosestPoint closestPointOnBody(const Body& body, const Eigen::Vector3d& p) {
  ClosestPoint cp;
  cp.face = body.bvh().faceTree().nearest(body.mesh(), p, cp.point);
  if (cp.face < 0) cp.point = p;
  cp.distance = (cp.point - p).norm();
  return cp;
}

namespace {

// Number of body faces the segment [p, q] crosses, walking the body's box tree.
int countSegmentCrossings(const Body& body, const Eigen::Vector3d& p, const Eigen::Vector3d& q) {
  const MatrixX3d& V = body.mesh().V;
  const MatrixX3i& F = body.mesh().F;
  const Eigen::Vector3d d = q - p;
  const Eigen::Vector3d invD(1.0 / d.x(), 1.0 / d.y(), 1.0 / d.z());
  int hits = 0;
  body.bvh().faceTree().alongSegment(p, invD, [&](int f) {
    const Eigen::Vector3d a = V.row(F(f, 0)), b = V.row(F(f, 1)), c = V.row(F(f, 2));
    // Either orientation: a ray counts every surface it passes through.
    if (segmentCrossesTriangle(p, q, a, b, c) || segmentCrossesTriangle(q, p, a, b, c)) ++hits;
  });
  return hits;
}

}  // namespace

bool pointInsideBody(const Body& body, const Eigen::Vector3d& p) {
  if (!body.closed()) return false;
  const Eigen::Vector3d& lo = body.boxMin();
  const Eigen::Vector3d& hi = body.boxMax();
  if ((p.array() < lo.array()).any() || (p.array() > hi.array()).any()) return false;
  const double L = 4.0 * (hi - lo).norm() + 1.0;
  static const Eigen::Vector3d dirs[3] = {
      Eigen::Vector3d(0.5773, 0.5774, 0.5775).normalized(),
      Eigen::Vector3d(-0.7071, 0.0123, 0.7069).normalized(),
      Eigen::Vector3d(0.0311, -0.9993, -0.0209).normalized()};
  int votes = 0;
  for (const auto& d : dirs) votes += countSegmentCrossings(body, p, p + L * d) & 1;
  return votes >= 2;
}

}  // namespace virtual_tryon
