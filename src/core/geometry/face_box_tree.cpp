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

namespace {

constexpr int kBins = 16;  // a node's faces go into this many bins by centre

// Boxes joined bin by bin (a node's faces binned, then bins swept from either end).
struct BinBox {
  Eigen::Vector3d lo, hi;
  int count = 0;
  void add(const Eigen::Vector3d& l, const Eigen::Vector3d& h, int n) {
    lo = count ? Eigen::Vector3d(lo.cwiseMin(l)) : l;
    hi = count ? Eigen::Vector3d(hi.cwiseMax(h)) : h;
    count += n;
  }
  void add(const BinBox& b) {
    if (b.count) add(b.lo, b.hi, b.count);
  }
  // Half the box's surface times its faces: the surface-area heuristic's cost.
  double cost() const {
    const Eigen::Vector3d d = hi - lo;
    return count ? (d.x() * d.y() + d.y() * d.z() + d.z() * d.x()) * count : 0.0;
  }
};

// The bin whose left and right sides together cost least: faces in bins 0 .. returned value go
// left. -1 when no split leaves faces on both sides.
int cheapestSplit(const BinBox (&bins)[kBins], int count) {
  double above[kBins] = {};  // above[b]: the cost of bins b .. kBins - 1 together
  BinBox right;
  for (int b = kBins - 1; b > 0; --b) {
    right.add(bins[b]);
    above[b] = right.cost();
  }
  int best = -1;
  double bestCost = std::numeric_limits<double>::infinity();
  BinBox left;
  for (int b = 0; b + 1 < kBins; ++b) {
    left.add(bins[b]);
    if (left.count == 0 || left.count == count) continue;
    const double cost = left.cost() + above[b + 1];
    if (cost < bestCost) {
      bestCost = cost;
      best = b;
    }
  }
  return best;
}

}  // namespace

// The faces' boxes and centres, then the tree depth first. (Building the root's two halves on two
// threads took longer on a 2-core VM: 6.6-8.0 ms against 6.0 on body_hm08.)
FaceBoxTree::FaceBoxTree(const TriMesh& mesh) {
  const int nf = static_cast<int>(mesh.F.rows());
  if (nf == 0) return;
  box_.resize(static_cast<std::size_t>(nf));
  Build b;
  b.centre.resize(static_cast<std::size_t>(nf));
  b.bin.resize(static_cast<std::size_t>(nf));
  for (int f = 0; f < nf; ++f) {
    faceBox(mesh.V, mesh.F, f);
    b.centre[static_cast<std::size_t>(f)] = 0.5 * (box_[f].lo + box_[f].hi);
  }
  order_.resize(static_cast<std::size_t>(nf));
  std::iota(order_.begin(), order_.end(), 0);
  nodes_.reserve(2 * static_cast<std::size_t>(nf));  // at most 2 nf - 1 nodes, whatever the splits
  build(b, nodes_, 0, nf, 0);
}

// Node `id` of `nodes` over order_[first .. first + count), then its subtrees after it.
int FaceBoxTree::build(Build& b, std::vector<Node>& nodes, int first, int count, int depth) {
  const int id = static_cast<int>(nodes.size());
  nodes.emplace_back();
  const int half = fitAndSplit(b, nodes[static_cast<std::size_t>(id)], first, count, depth);
  if (half == 0) return id;
  const int left = build(b, nodes, first, half, depth + 1);
  const int right = build(b, nodes, first + half, count - half, depth + 1);
  nodes[static_cast<std::size_t>(id)].left = left;
  nodes[static_cast<std::size_t>(id)].right = right;
  return id;
}

// Fits `node` to the faces order_[first .. first + count); a leaf (up to kLeafFaces faces, or at
// kMaxDepth) keeps them and 0 is returned, else they are split (sahSplit) and the left count is.
int FaceBoxTree::fitAndSplit(Build& b, Node& node, int first, int count, int depth) {
  node.lo = box_[order_[first]].lo;
  node.hi = box_[order_[first]].hi;
  Eigen::Vector3d clo = b.centre[order_[first]], chi = clo;
  for (int i = first + 1; i < first + count; ++i) {
    const int f = order_[static_cast<std::size_t>(i)];
    node.lo = node.lo.cwiseMin(box_[f].lo);
    node.hi = node.hi.cwiseMax(box_[f].hi);
    clo = clo.cwiseMin(b.centre[f]);
    chi = chi.cwiseMax(b.centre[f]);
  }
  if (count <= kLeafFaces || depth == kMaxDepth) {
    node.first = first;
    node.count = count;
    return 0;
  }
  int axis = 0;
  (chi - clo).maxCoeff(&axis);
  return sahSplit(b, first, count, axis, clo[axis], chi[axis]);
}

// Binned surface-area split of order_[first .. first + count) along `axis` (centres from c0 to c1):
// the faces are put in kBins bins by centre, the split between bins that minimises
// area(left box) * left count + area(right box) * right count is taken (cheapestSplit), and
// order_ partitioned at it. Returns the left count; when every centre falls in one bin, the median.
int FaceBoxTree::sahSplit(Build& b, int first, int count, int axis, double c0, double c1) {
  const double width = c1 - c0;
  BinBox bins[kBins];
  for (int i = first; i < first + count; ++i) {
    const int f = order_[static_cast<std::size_t>(i)];
    const int k = width > 0 ? std::min(kBins - 1, static_cast<int>((b.centre[f][axis] - c0) / width * kBins)) : 0;
    b.bin[static_cast<std::size_t>(f)] = static_cast<unsigned char>(k);
    bins[k].add(box_[f].lo, box_[f].hi, 1);
  }
  const int best = cheapestSplit(bins, count);
  if (best < 0) {
    const int half = count / 2;
    std::nth_element(order_.begin() + first, order_.begin() + first + half, order_.begin() + first + count,
                     [&](int x, int y) { return b.centre[x][axis] < b.centre[y][axis]; });
    return half;
  }
  return static_cast<int>(std::partition(order_.begin() + first, order_.begin() + first + count,
                                         [&](int f) { return b.bin[static_cast<std::size_t>(f)] <= best; }) -
                          (order_.begin() + first));
}

// Children come after their parent in nodes_, so a backward pass sees them first.
void FaceBoxTree::refitNodes() {
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
