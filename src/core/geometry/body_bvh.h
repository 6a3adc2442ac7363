// Internal to the core: the body's face tree, built once per body and refitted for each new frame
// of a moving one.
#pragma once

#include "virtual_tryon/core/geometry/mesh.h"

#include "core/geometry/face_box_tree.h"

#include <memory>

namespace virtual_tryon {

// One box tree over the body's triangles (face_box_tree.h) serves every body query: the edge-face
// detection, the nearest point and the ray-parity inside test. A new frame of a moving body refits
// it in place (refit): the same tree, new boxes, not rebuilt.
class BodyBVH {
 public:
  explicit BodyBVH(const TriMesh& mesh) : tree_(mesh) {}
  const FaceBoxTree& faceTree() const { return tree_; }
  // The same faces on new vertex positions (not while anyone queries the tree); perFace(a, b, c)
  // sees each face's corners on the way (FaceBoxTree::refit).
  template <class PerFace>
  void refit(const TriMesh& mesh, PerFace&& perFace) {
    tree_.refit(mesh.V, mesh.F, perFace);
  }
  std::unique_ptr<BodyBVH> copy() const { return std::make_unique<BodyBVH>(*this); }

 private:
  FaceBoxTree tree_;
};

}  // namespace virtual_tryon
