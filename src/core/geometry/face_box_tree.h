// Internal to the core: an axis-aligned box tree over the triangles of one mesh (binned
// surface-area splits, leaves of up to 4 faces). It serves every body query: the edge-face
// detection (box-overlapping pairs handed over directly, where FCL's mesh-mesh traversal would run
// a triangle-triangle test on each first), the nearest point and the ray-parity inside test; its
// boxes are refitted in place when the vertices move and the faces stay.
#pragma once

#include "virtual_tryon/core/geometry/mesh.h"

#include <algorithm>
#include <vector>

namespace virtual_tryon {

class FaceBoxTree {
 public:
  static constexpr int kLeafFaces = 4;
  static constexpr int kMaxDepth = 60;  // a deeper node is a leaf, whatever its size (the walks' stacks hold 128)

  FaceBoxTree() = default;
  // Built over mesh's faces: each node split by a binned surface-area rule (sahSplit), a subtree
  // of up to kLeafFaces faces one leaf.
  explicit FaceBoxTree(const TriMesh& mesh);

  // Calls visit(face) for every face whose closed bounding box overlaps [lo, hi].
  template <class Visit>
  void overlapping(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi, Visit&& visit) const;

  // Calls visit(face) for every face whose closed bounding box the segment [p, p + d] meets
  // (invD: 1 / d per axis).
  template <class Visit>
  void alongSegment(const Eigen::Vector3d& p, const Eigen::Vector3d& invD, Visit&& visit) const;

  // The face nearest to p and the nearest point on it (branch and bound over the boxes; faces of
  // equal distance: the first found). `mesh` is the mesh the tree was built over. -1 when empty.
  int nearest(const TriMesh& mesh, const Eigen::Vector3d& p, Eigen::Vector3d& point) const;

  // New vertex positions, same faces: every box grown or shrunk to fit (the split stays), calling
  // perFace(a, b, c) with each face's corners, in face order, on the way (one pass over the faces
  // for both: a moving body sums its volume there).
  template <class PerFace>
  void refit(const MatrixX3d& V, const MatrixX3i& F, PerFace&& perFace);
  bool empty() const { return nodes_.empty(); }

  // Whether face f's bounding box, as the tree holds it (as built or last refitted), overlaps the
  // closed box [lo, hi].
  bool faceOverlaps(int f, const Eigen::Vector3d& lo, const Eigen::Vector3d& hi) const {
    const Box& b = box_[static_cast<std::size_t>(f)];
    return (b.lo.array() <= hi.array()).all() && (lo.array() <= b.hi.array()).all();
  }

 private:
  // The binary tree as the build makes it, depth first (a node's children after it); its boxes
  // are the walks' nodes' (refitNodes).
  struct Split {
    int left = -1, right = -1;  // children; -1 for a leaf
    int first = 0, count = 0;   // leaf: faces order_[first .. first + count)
  };
  // The tree as the walks read it: each inner node of the build holds both of its children's
  // boxes, so that a walk tests both with one fetch and never fetches a child whose box it misses.
  // Child k: child[k] >= 0 an inner node; else a leaf of count[k] faces, order_[-child[k] - 1 ..]
  // (count 0: no child, in the root of a tree of one leaf; its box is empty, lo above hi).
  struct Node {
    Eigen::Vector3d lo[2] = {Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero()};
    Eigen::Vector3d hi[2] = {Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero()};
    int child[2] = {-1, -1};
    int count[2] = {0, 0};
  };
  // What a build reads and writes besides the tree: each face's centre and, within one split, its
  // bin.
  struct Build {
    std::vector<Eigen::Vector3d> centre;
    std::vector<unsigned char> bin;
  };
  int build(Build& b, std::vector<Split>& splits, int first, int count, int depth);
  int splitOrLeaf(Build& b, Split& node, int first, int count, int depth);
  int sahSplit(Build& b, int first, int count, int axis, double c0, double c1);
  int adopt(const std::vector<Split>& splits, int s);
  void faceBox(const MatrixX3d& V, const MatrixX3i& F, int f);
  void refitNodes();  // every node's child boxes to their faces' boxes, bottom up
  // Depth first from the root: a child whose box meets(lo, hi) is entered (an inner node) or has
  // each of its faces whose box meets(...) visited (a leaf). meets must refuse the empty box.
  template <class Meets, class Visit>
  void walk(Meets& meets, Visit& visit) const;
  std::vector<Node> nodes_;
  std::vector<int> order_;
  struct Box {
    Eigen::Vector3d lo, hi;
  };
  std::vector<Box> box_;  // per face, both corners side by side (one memory fetch per test)
};

template <class PerFace>
void FaceBoxTree::refit(const MatrixX3d& V, const MatrixX3i& F, PerFace&& perFace) {
  for (Eigen::Index f = 0; f < F.rows(); ++f) {
    const Eigen::Vector3d a = V.row(F(f, 0)), b = V.row(F(f, 1)), c = V.row(F(f, 2));
    Box& box = box_[static_cast<std::size_t>(f)];
    box.lo = a.cwiseMin(b).cwiseMin(c);
    box.hi = a.cwiseMax(b).cwiseMax(c);
    perFace(a, b, c);
  }
  refitNodes();
}

template <class Meets, class Visit>
void FaceBoxTree::walk(Meets& meets, Visit& visit) const {
  if (nodes_.empty()) return;
  int stack[128];
  int top = 0;
  stack[top++] = 0;
  while (top > 0) {
    const Node& n = nodes_[static_cast<std::size_t>(stack[--top])];
    for (int k = 0; k < 2; ++k) {
      if (!meets(n.lo[k], n.hi[k])) continue;
      if (n.child[k] >= 0) {
        stack[top++] = n.child[k];
        continue;
      }
      for (int i = -n.child[k] - 1, end = i + n.count[k]; i < end; ++i) {
        const int f = order_[static_cast<std::size_t>(i)];
        const Box& b = box_[static_cast<std::size_t>(f)];
        if (meets(b.lo, b.hi)) visit(f);
      }
    }
  }
}

template <class Visit>
void FaceBoxTree::overlapping(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi, Visit&& visit) const {
  auto meets = [&](const Eigen::Vector3d& blo, const Eigen::Vector3d& bhi) {
    return (blo.array() <= hi.array()).all() && (lo.array() <= bhi.array()).all();
  };
  walk(meets, visit);
}

namespace face_box_tree_detail {
// Does the segment [p, p + d] (invD = 1 / d per axis) meet the closed box [lo, hi]? (slab test)
inline bool segmentMeetsBox(const Eigen::Vector3d& p, const Eigen::Vector3d& invD, const Eigen::Vector3d& lo,
                            const Eigen::Vector3d& hi) {
  double t0 = 0, t1 = 1;
  for (int k = 0; k < 3; ++k) {
    double a = (lo[k] - p[k]) * invD[k], b = (hi[k] - p[k]) * invD[k];
    if (a > b) std::swap(a, b);
    t0 = std::max(t0, a);
    t1 = std::min(t1, b);
    if (t0 > t1) return false;
  }
  return true;
}
}  // namespace face_box_tree_detail

template <class Visit>
void FaceBoxTree::alongSegment(const Eigen::Vector3d& p, const Eigen::Vector3d& invD, Visit&& visit) const {
  auto meets = [&](const Eigen::Vector3d& lo, const Eigen::Vector3d& hi) {
    return lo.x() <= hi.x() && face_box_tree_detail::segmentMeetsBox(p, invD, lo, hi);  // not the empty box
  };
  walk(meets, visit);
}

}  // namespace virtual_tryon
