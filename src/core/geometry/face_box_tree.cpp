#include "core/geometry/face_box_tree.h"

#include "virtual_tryon/core/geometry/point_queries.h"

#include <algorithm>
#include <limits>
#include <numeric>

namespace virtual_tryon {

namespace {
double boxDistance2(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi, const Eigen::Vector3d& p) {
  return (lo - p).cwiseMax(p - hi).cwiseMax(0.0).squaredNorm();
}
}  // namespace

void FaceBoxTree::faceBox(const MatrixX3d& V, const MatrixX3i& F, int f) {
  Eigen::Vector3d lo = V.row(F(f, 0)).transpose(), hi = lo;
  for (int k = 1; k < 3; ++k) {
    lo = lo.cwiseMin(V.row(F(f, k)).transpose());
    hi = hi.cwiseMax(V.row(F(f, k)).transpose());
  }
  box_[static_cast<std::size_t>(f)].lo = lo;
  box_[static_cast<std::size_t>(f)].hi = hi;
}

FaceBoxTree::FaceBoxTree(const TriMesh& mesh) {
  const int nf = static_cast<int>(mesh.F.rows());
  if (nf == 0) return;
  box_.resize(static_cast<std::size_t>(nf));
  std::vector<Eigen::Vector3d> centre(static_cast<std::size_t>(nf));
  for (int f = 0; f < nf; ++f) {
    faceBox(mesh.V, mesh.F, f);
    centre[static_cast<std::size_t>(f)] = 0.5 * (box_[f].lo + box_[f].hi);
  }
  order_.resize(static_cast<std::size_t>(nf));
  std::iota(order_.begin(), order_.end(), 0);
  nodes_.reserve(static_cast<std::size_t>(2 * nf / kLeafFaces + 2));
  build(centre, 0, nf, 0);
}

// Binned surface-area split of order_[first .. first + count) along `axis` (centres from c0 to c1):
// the faces are put in kBins bins by centre, the split between bins that minimises
// area(left box) * left count + area(right box) * right count is taken, and order_ partitioned at
// it. Returns the left count; when every centre falls in one bin, the median.
int FaceBoxTree::sahSplit(const std::vector<Eigen::Vector3d>& centre, int first, int count, int axis, double c0,
                          double c1) {
  constexpr int kBins = 16;
  const double width = c1 - c0;
  auto binOf = [&](int f) {
    return width > 0 ? std::min(kBins - 1, static_cast<int>((centre[f][axis] - c0) / width * kBins)) : 0;
  };
  Eigen::Vector3d blo[kBins], bhi[kBins];
  int n[kBins] = {};
  for (int i = first; i < first + count; ++i) {
    const int f = order_[static_cast<std::size_t>(i)];
    const int b = binOf(f);
    blo[b] = n[b] ? Eigen::Vector3d(blo[b].cwiseMin(box_[f].lo)) : box_[f].lo;
    bhi[b] = n[b] ? Eigen::Vector3d(bhi[b].cwiseMax(box_[f].hi)) : box_[f].hi;
    ++n[b];
  }
  auto area = [](const Eigen::Vector3d& lo, const Eigen::Vector3d& hi) {
    const Eigen::Vector3d d = hi - lo;
    return d.x() * d.y() + d.y() * d.z() + d.z() * d.x();
  };
  double rightCost[kBins] = {};
  {
    Eigen::Vector3d lo, hi;
    int m = 0;
    for (int b = kBins - 1; b > 0; --b) {
      if (n[b]) {
        lo = m ? Eigen::Vector3d(lo.cwiseMin(blo[b])) : blo[b];
        hi = m ? Eigen::Vector3d(hi.cwiseMax(bhi[b])) : bhi[b];
        m += n[b];
      }
      rightCost[b] = m ? area(lo, hi) * m : 0;
    }
  }
  int best = -1;
  double bestCost = std::numeric_limits<double>::infinity();
  Eigen::Vector3d lo, hi;
  int m = 0;
  for (int b = 0; b + 1 < kBins; ++b) {
    if (n[b]) {
      lo = m ? Eigen::Vector3d(lo.cwiseMin(blo[b])) : blo[b];
      hi = m ? Eigen::Vector3d(hi.cwiseMax(bhi[b])) : bhi[b];
      m += n[b];
    }
    if (m == 0 || m == count) continue;
    const double cost = area(lo, hi) * m + rightCost[b + 1];
    if (cost < bestCost) {
      bestCost = cost;
      best = b;
    }
  }
  if (best < 0) {
    const int half = count / 2;
    std::nth_element(order_.begin() + first, order_.begin() + first + half, order_.begin() + first + count,
                     [&](int a, int b) { return centre[a][axis] < centre[b][axis]; });
    return half;
  }
  return static_cast<int>(std::partition(order_.begin() + first, order_.begin() + first + count,
                                         [&](int f) { return binOf(f) <= best; }) -
                          (order_.begin() + first));
}

int FaceBoxTree::build(const std::vector<Eigen::Vector3d>& centre, int first, int count, int depth) {
  const int id = static_cast<int>(nodes_.size());
  nodes_.emplace_back();
  Eigen::Vector3d lo = box_[order_[first]].lo, hi = box_[order_[first]].hi;
  Eigen::Vector3d clo = centre[order_[first]], chi = clo;
  for (int i = first + 1; i < first + count; ++i) {
    const int f = order_[static_cast<std::size_t>(i)];
    lo = lo.cwiseMin(box_[f].lo);
    hi = hi.cwiseMax(box_[f].hi);
    clo = clo.cwiseMin(centre[f]);
    chi = chi.cwiseMax(centre[f]);
  }
  nodes_[id].lo = lo;
  nodes_[id].hi = hi;
  if (count <= kLeafFaces || depth == kMaxDepth) {
    nodes_[id].first = first;
    nodes_[id].count = count;
    return id;
  }
  int axis = 0;
  (chi - clo).maxCoeff(&axis);
  const int half = sahSplit(centre, first, count, axis, clo[axis], chi[axis]);
  const int left = build(centre, first, half, depth + 1);
  const int right = build(centre, first + half, count - half, depth + 1);
  nodes_[id].left = left;
  nodes_[id].right = right;
  return id;
}

void FaceBoxTree::refit(const MatrixX3d& V, const MatrixX3i& F) {
  for (Eigen::Index f = 0; f < F.rows(); ++f) faceBox(V, F, static_cast<int>(f));
  // Children come after their parent in nodes_, so a backward pass sees them first.
  for (int id = static_cast<int>(nodes_.size()) - 1; id >= 0; --id) {
    Node& n = nodes_[static_cast<std::size_t>(id)];
    if (n.left >= 0) {
      n.lo = nodes_[n.left].lo.cwiseMin(nodes_[n.right].lo);
      n.hi = nodes_[n.left].hi.cwiseMax(nodes_[n.right].hi);
      continue;
    }
    n.lo = box_[order_[n.first]].lo;
    n.hi = box_[order_[n.first]].hi;
    for (int i = n.first + 1; i < n.first + n.count; ++i) {
      n.lo = n.lo.cwiseMin(box_[order_[i]].lo);
      n.hi = n.hi.cwiseMax(box_[order_[i]].hi);
    }
  }
}

int FaceBoxTree::nearest(const TriMesh& mesh, const Eigen::Vector3d& p, Eigen::Vector3d& point) const {
  if (nodes_.empty()) return -1;
  int best = -1;
  double bestD = std::numeric_limits<double>::infinity();
  int stack[128];
  int top = 0;
  stack[top++] = 0;
  while (top > 0) {
    const Node& n = nodes_[static_cast<std::size_t>(stack[--top])];
    if (boxDistance2(n.lo, n.hi, p) >= bestD) continue;
    if (n.left < 0) {
      for (int i = n.first; i < n.first + n.count; ++i) {
        const int f = order_[static_cast<std::size_t>(i)];
        const Eigen::Vector3d q = closestPointOnTriangle(p, mesh.V.row(mesh.F(f, 0)).transpose(),
                                                         mesh.V.row(mesh.F(f, 1)).transpose(),
                                                         mesh.V.row(mesh.F(f, 2)).transpose());
        const double d = (q - p).squaredNorm();
        if (d < bestD) {
          bestD = d;
          best = f;
          point = q;
        }
      }
      continue;
    }
    // The nearer child last, so it is searched first.
    const Node& l = nodes_[static_cast<std::size_t>(n.left)];
    const Node& r = nodes_[static_cast<std::size_t>(n.right)];
    const bool leftNearer = boxDistance2(l.lo, l.hi, p) <= boxDistance2(r.lo, r.hi, p);
    stack[top++] = leftNearer ? n.right : n.left;
    stack[top++] = leftNearer ? n.left : n.right;
  }
  return best;
}

}  // namespace virtual_tryon
