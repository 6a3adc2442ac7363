#include "virtual_tryon/core/geometry/rigid_transform.h"

namespace virtual_tryon {

void transformMesh(const Eigen::Isometry3d& T, TriMesh& mesh) {
  for (Eigen::Index i = 0; i < mesh.V.rows(); ++i)
    mesh.V.row(i) = (T * Eigen::Vector3d(mesh.V.row(i).transpose())).transpose();
}

Eigen::Isometry3d zUpWorldFromBody(const TriMesh& body, const Eigen::Vector3d& up) {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = Eigen::Quaterniond::FromTwoVectors(up, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  if (body.V.rows() > 0) T.translation().z() = -(body.V * T.linear().row(2).transpose()).minCoeff();
  return T;
}

}  // namespace virtual_tryon
