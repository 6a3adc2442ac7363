// Rigid motions of meshes: an isometry (a rotation and a translation, as tf2 gives between two
// frames) applied to every vertex, so that a mesh given in one frame can be used in another.
#pragma once

#include "virtual_tryon/core/geometry/mesh.h"

#include <Eigen/Geometry>

namespace virtual_tryon {

// Moves every vertex of `mesh` by T (v -> T * v, in place); the faces do not change.
void transformMesh(const Eigen::Isometry3d& T, TriMesh& mesh);

// The pose of a body's frame in a z-up world (REP 103), for a mesh whose up axis is `up` (non-zero;
// MakeHuman's and ours: +y): the shortest rotation taking `up` to +z, then a lift that puts the
// mesh's lowest point on z = 0, so that the body stands on the world's floor. A mesh with no
// vertices gets the rotation alone.
Eigen::Isometry3d zUpWorldFromBody(const TriMesh& body, const Eigen::Vector3d& up);

}  // namespace virtual_tryon
