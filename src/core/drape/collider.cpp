#include "virtual_tryon/core/drape/collider.h"

#include "virtual_tryon/core/geometry/point_queries.h"

namespace virtual_tryon {

bool ObjectSpaceCollider::collide(const Eigen::Vector3d& p, Eigen::Vector3d& normal, double& depth) const {
  const ClosestPoint cp = closestPointOnBody(body_, p);
  if (cp.face < 0) return false;
  const Eigen::Vector3d n = body_.faceNormal(cp.face);
  const bool outside = n.dot(p - cp.point) >= 0;
  if (outside && cp.distance >= tol_) return false;
  normal = n;
  depth = outside ? tol_ - cp.distance : tol_ + cp.distance;
  return true;
}

}  // namespace virtual_tryon
