// Rigid motions of meshes: an isometry (a rotation and a translation, as tf2 gives between two
// frames) applied to every vertex, so that a mesh given in one frame can be used in another.
#pragma once

#include "virtual_tryon/core/geometry/mesh.h"

#include <Eigen/Geometry>

namespace virtual_tryon {

// Moves every vertex of `mesh` by T (v -> T * v, in place); the faces do not change.
void transformMesh(const Eigen::Isometry3d& T, TriMesh& mesh);

}  // namespace virtual_tryon
