#include "virtual_tryon/core/collider.h"

#include "virtual_tryon/core/point_queries.h"

namespace virtual_tryon {

bool ObjectSpaceCollider::collide(const Eigen::Vector3d& p, Eigen::Vector3d& normal) const {
  const ClosestPoint cp = closestPointOnBody(body_, p);
  if (cp.face < 0) return false;
  if (cp.distance >= tol_) {
    // Far enough out, or deep inside: the sign decides.
    const Eigen::Vector3d n = body_.faceNormals().row(cp.face).transpose();
    if (n.dot(p - cp.point) >= 0) return false;
  }
  normal = body_.faceNormals().row(cp.face).transpose();
  return true;
}

}  // namespace virtual_tryon
