// The independent referee of reference_check.h, accelerated: the same predicates (Moller-Trumbore
// segment tests with the same bounding-box filter, three-ray parity, point-triangle distance) and
// so the same counts, but the candidate faces come from the referee's own AABB trees instead of a
// loop over every face. Shares no code with the resolver's detector (no FCL, no
// segmentCrossesTriangle). For the evaluation, where the brute-force O(#E * #F) count is too slow
// (counts after every resolver iteration, 50k-vertex garments).
#pragma once

#include "virtual_tryon/core/geometry/mesh.h"
#include "virtual_tryon/testing/reference_check.h"

#include <vector>

namespace virtual_tryon {

// An axis-aligned box tree over the triangles of one mesh (median split, leaves of up to 4).
class ReferenceTree {
 public:
  ReferenceTree() = default;
  explicit ReferenceTree(const TriMesh& mesh);
  // Calls visit(face) for every face whose (closed) bounding box overlaps [lo, hi].
  template <class Visit>
  void overlapping(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi, Visit&& visit) const;
  // Faces whose box (grown by a relative 1e-9) the segment p + t d, t in [0, 1], may meet.
  template <class Visit>
  void alongSegment(const Eigen::Vector3d& p, const Eigen::Vector3d& d, Visit&& visit) const;
  // Distance from p to the nearest triangle (+inf for an empty mesh).
  double distance(const TriMesh& mesh, const Eigen::Vector3d& p) const;
  bool empty() const { return nodes_.empty(); }

 private:
  struct Node {
    Eigen::Vector3d lo, hi;
    int left = -1, right = -1;  // children; -1 for a leaf
    int first = 0, count = 0;   // leaf: faces order_[first .. first + count)
  };
  int build(const std::vector<Eigen::Vector3d>& lo, const std::vector<Eigen::Vector3d>& hi,
            const std::vector<Eigen::Vector3d>& centre, int first, int count);
  std::vector<Node> nodes_;
  std::vector<int> order_;
  std::vector<Eigen::Vector3d> face_lo_, face_hi_;
};

class ReferenceReferee {
 public:
  // Builds the body's tree once; count() may then be called for many garments (or states).
  explicit ReferenceReferee(const TriMesh& body);
  // Equal to referenceCounts(body, garment, countInside, eps).
  ReferenceCounts count(const TriMesh& garment, bool countInside = true, double eps = 1e-12) const;
  // Per garment vertex: inside the (closed) body by the three-ray parity vote, and the distance
  // to the body surface (NaN for vertices outside).
  void inside(const TriMesh& garment, std::vector<char>& inside, std::vector<double>* depth = nullptr) const;
  // Per garment vertex: the distance to the body surface, negative for vertices inside.
  std::vector<double> signedDistances(const TriMesh& garment) const;
  const TriMesh& body() const { return body_; }

 private:
  TriMesh body_;
  MatrixX2i body_edges_;
  ReferenceTree tree_;
  Eigen::Vector3d lo_, hi_;
};

// ---------------------------------------------------------------------------------------------

template <class Visit>
void ReferenceTree::overlapping(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi, Visit&& visit) const {
  if (nodes_.empty()) return;
  int stack[128];
  int top = 0;
  stack[top++] = 0;
  while (top > 0) {
    const Node& n = nodes_[stack[--top]];
    if ((n.lo.array() > hi.array()).any() || (lo.array() > n.hi.array()).any()) continue;
    if (n.left < 0) {
      for (int i = n.first; i < n.first + n.count; ++i) {
        const int f = order_[i];
        if ((face_lo_[f].array() <= hi.array()).all() && (lo.array() <= face_hi_[f].array()).all()) visit(f);
      }
    } else {
      stack[top++] = n.left;
      stack[top++] = n.right;
    }
  }
}

template <class Visit>
void ReferenceTree::alongSegment(const Eigen::Vector3d& p, const Eigen::Vector3d& d, Visit&& visit) const {
  if (nodes_.empty()) return;
  auto hits = [&](const Eigen::Vector3d& lo, const Eigen::Vector3d& hi) {
    const Eigen::Vector3d pad = 1e-9 * ((hi - lo).cwiseAbs().array() + 1e-9 + p.cwiseAbs().array()).matrix();
    double t0 = 0, t1 = 1;
    for (int k = 0; k < 3; ++k) {
      const double a = lo[k] - pad[k], b = hi[k] + pad[k];
      if (d[k] == 0) {
        if (p[k] < a || p[k] > b) return false;
        continue;
      }
      double ta = (a - p[k]) / d[k], tb = (b - p[k]) / d[k];
      if (ta > tb) std::swap(ta, tb);
      t0 = std::max(t0, ta);
      t1 = std::min(t1, tb);
      if (t0 > t1) return false;
    }
    return true;
  };
  int stack[128];
  int top = 0;
  stack[top++] = 0;
  while (top > 0) {
    const Node& n = nodes_[stack[--top]];
    if (!hits(n.lo, n.hi)) continue;
    if (n.left < 0) {
      for (int i = n.first; i < n.first + n.count; ++i)
        if (hits(face_lo_[order_[i]], face_hi_[order_[i]])) visit(order_[i]);
    } else {
      stack[top++] = n.left;
      stack[top++] = n.right;
    }
  }
}

}  // namespace virtual_tryon
