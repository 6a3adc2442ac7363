// Internal to the core: an axis-aligned box tree over the triangles of one mesh (median split on
// the longest axis of the centroids, leaves of up to 4 faces), for the edge-face detection. FCL's
// mesh-mesh traversal runs a triangle-triangle test on every overlapping pair before the
// detection's own segment tests see it; this tree hands over the box-overlapping pairs directly,
// and its boxes can be refitted in place when the vertices move and the faces stay.
#pragma once

#include "virtual_tryon/core/geometry/mesh.h"

#include <vector>

namespace virtual_tryon {

class FaceBoxTree {
 public:
  FaceBoxTree() = default;
  explicit FaceBoxTree(const TriMesh& mesh);

  // Calls visit(face) for every face whose closed bounding box overlaps [lo, hi].
  template <class Visit>
  void overlapping(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi, Visit&& visit) const;

  // The face nearest to p and the nearest point on it (branch and bound over the boxes; faces of
  // equal distance: the first found). `mesh` is the mesh the tree was built over. -1 when empty.
  int nearest(const TriMesh& mesh, const Eigen::Vector3d& p, Eigen::Vector3d& point) const;

  // New vertex positions, same faces: every box grown or shrunk to fit (the split stays).
  void refit(const MatrixX3d& V, const MatrixX3i& F);
  bool empty() const { return nodes_.empty(); }

  // Whether face f's bounding box, as the tree holds it (as built or last refitted), overlaps the
  // closed box [lo, hi].
  bool faceOverlaps(int f, const Eigen::Vector3d& lo, const Eigen::Vector3d& hi) const {
    const Box& b = box_[static_cast<std::size_t>(f)];
    return (b.lo.array() <= hi.array()).all() && (lo.array() <= b.hi.array()).all();
  }

 private:
  struct Node {
    Eigen::Vector3d lo, hi;
    int left = -1, right = -1;  // children; -1 for a leaf
    int first = 0, count = 0;   // leaf: faces order_[first .. first + count)
  };
  int build(const std::vector<Eigen::Vector3d>& centre, int first, int count);
  void faceBox(const MatrixX3d& V, const MatrixX3i& F, int f);
  std::vector<Node> nodes_;
  std::vector<int> order_;
  struct Box {
    Eigen::Vector3d lo, hi;
  };
  std::vector<Box> box_;  // per face, both corners side by side (one memory fetch per test)
};

template <class Visit>
void FaceBoxTree::overlapping(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi, Visit&& visit) const {
  if (nodes_.empty()) return;
  int stack[128];
  int top = 0;
  stack[top++] = 0;
  while (top > 0) {
    const Node& n = nodes_[static_cast<std::size_t>(stack[--top])];
    if ((n.lo.array() > hi.array()).any() || (lo.array() > n.hi.array()).any()) continue;
    if (n.left >= 0) {
      stack[top++] = n.left;
      stack[top++] = n.right;
      continue;
    }
    for (int i = n.first; i < n.first + n.count; ++i) {
      const int f = order_[static_cast<std::size_t>(i)];
      if (faceOverlaps(f, lo, hi)) visit(f);
    }
  }
}

}  // namespace virtual_tryon
