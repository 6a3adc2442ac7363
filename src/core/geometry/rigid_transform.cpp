#include "virtual_tryon/core/geometry/rigid_transform.h"

namespace virtual_tryon {

void transformMesh(const Eigen::Isometry3d& T, TriMesh& mesh) {
  for (Eigen::Index i = 0; i < mesh.V.rows(); ++i)
    mesh.V.row(i) = (T * Eigen::Vector3d(mesh.V.row(i).transpose())).transpose();
}

}  // namespace virtual_tryon
