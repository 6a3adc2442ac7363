#include "virtual_tryon/core/geometry/edge_face_crossing.h"

#include "virtual_tryon/core/geometry/mesh.h"

#include <Eigen/Geometry>

#include <cmath>

namespace virtual_tryon {
namespace {

bool lexLess(const Eigen::Vector3d& p, const Eigen::Vector3d& q) {
  if (p.x() != q.x()) return p.x() < q.x();
  if (p.y() != q.y()) return p.y() < q.y();
  return p.z() < q.z();
}

// Signed volume of (a, b, p, q) * 6, computed with p, q in canonical order.
double edgeVolume(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& p,
                  const Eigen::Vector3d& q) {
  const bool swap = lexLess(q, p);
  const Eigen::Vector3d& u = swap ? q : p;
  const Eigen::Vector3d& v = swap ? p : q;
  const Eigen::Vector3d ad = a - v, bd = b - v, ud = u - v;
  const double vol = ad.dot(crossProduct(bd, ud));
  return swap ? -vol : vol;
}

}  // namespace

bool segmentCrossesTriangle(const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                            const Eigen::Vector3d& p0, const Eigen::Vector3d& p1,
                            const Eigen::Vector3d& p2, EdgeFaceHit* hit) {
  const Eigen::Vector3d n = crossProduct(p1 - p0, p2 - p0);
  const double len = n.norm();
  if (!(len > 0)) return false;
  const double sa = n.dot(a - p0), sb = n.dot(b - p0);
  const bool crossesPlane = (sa < 0 && sb > 0) || (sa > 0 && sb < 0) || (sa == 0 && sb < 0) ||
                            (sb == 0 && sa < 0);
  if (!crossesPlane) return false;
  // Volumes of the segment with each edge; the crossing point is inside the closed triangle when
  // none has a sign opposite to the others.
  const double w2 = edgeVolume(a, b, p0, p1);  // weight of p2
  const double w0 = edgeVolume(a, b, p1, p2);  // weight of p0
  const double w1 = edgeVolume(a, b, p2, p0);  // weight of p1
  const bool anyPos = w0 > 0 || w1 > 0 || w2 > 0;
  const bool anyNeg = w0 < 0 || w1 < 0 || w2 < 0;
  if (anyPos && anyNeg) return false;
  const double sum = w0 + w1 + w2;
  if (sum == 0) return false;  // segment in the plane or numerically degenerate
  if (hit) {
    hit->sa = sa / len;
    hit->sb = sb / len;
    hit->t = sa / (sa - sb);
    hit->bary = Eigen::Vector3d(w0, w1, w2) / sum;
  }
  return true;
}

}  // namespace virtual_tryon
