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
  std::vector<Split> splits;
  splits.reserve(2 * static_cast<std::size_t>(nf));  // at most 2 nf - 1 nodes, whatever the splits
  build(b, splits, 0, nf, 0);
  nodes_.reserve(splits.size() / 2 + 1);
  if (splits[0].left >= 0) {
    adopt(splits, 0);
  } else {  // one leaf: a root with it as its one child
    Node root;
    root.child[0] = -splits[0].first - 1;
    root.count[0] = splits[0].count;
    nodes_.push_back(root);
  }
  refitNodes();
}

// The walks' node for inner split s, then those of its inner children (depth first, as built).
int FaceBoxTree::adopt(const std::vector<Split>& splits, int s) {
  const int id = static_cast<int>(nodes_.size());
  nodes_.emplace_back();
  const int children[2] = {splits[static_cast<std::size_t>(s)].left, splits[static_cast<std::size_t>(s)].right};
  for (int k = 0; k < 2; ++k) {
    const Split& c = splits[static_cast<std::size_t>(children[k])];
    if (c.left < 0) {
      nodes_[static_cast<std::size_t>(id)].child[k] = -c.first - 1;
      nodes_[static_cast<std::size_t>(id)].count[k] = c.count;
    } else {
      const int inner = adopt(splits, children[k]);
      nodes_[static_cast<std::size_t>(id)].child[k] = inner;
    }
  }
  return id;
}

// Split `id` of `splits` over order_[first .. first + count), then its subtrees after it.
int FaceBoxTree::build(Build& b, std::vector<Split>& splits, int first, int count, int depth) {
  const int id = static_cast<int>(splits.size());
  splits.emplace_back();
  const int half = splitOrLeaf(b, splits[static_cast<std::size_t>(id)], first, count, depth);
  if (half == 0) return id;
  const int left = build(b, splits, first, half, depth + 1);
  const int right = build(b, splits, first + half, count - half, depth + 1);
  splits[static_cast<std::size_t>(id)].left = left;
  splits[static_cast<std::size_t>(id)].right = right;
  return id;
}

// The faces order_[first .. first + count): a leaf (up to kLeafFaces faces, or at kMaxDepth)
// keeps them in `node` and 0 is returned, else they are split (sahSplit) and the left count is.
// The boxes are fitted once the tree is built (refitNodes).
int FaceBoxTree::splitOrLeaf(Build& b, Split& node, int first, int count, int depth) {
  if (count <= kLeafFaces || depth == kMaxDepth) {
    node.first = first;
    node.count = count;
    return 0;
  }
  Eigen::Vector3d clo = b.centre[order_[first]], chi = clo;
  for (int i = first + 1; i < first + count; ++i) {
    const int f = order_[static_cast<std::size_t>(i)];
    clo = clo.cwiseMin(b.centre[f]);
    chi = chi.cwiseMax(b.centre[f]);
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
    for (int k = 0; k < 2; ++k) {
      if (n.child[k] >= 0) {
        const Node& c = nodes_[static_cast<std::size_t>(n.child[k])];
        n.lo[k] = c.lo[0].cwiseMin(c.lo[1]);
        n.hi[k] = c.hi[0].cwiseMax(c.hi[1]);
        continue;
      }
      n.lo[k] = Eigen::Vector3d::Constant(std::numeric_limits<double>::infinity());
      n.hi[k] = -n.lo[k];
      for (int i = -n.child[k] - 1, end = i + n.count[k]; i < end; ++i) {
        const Box& b = box_[static_cast<std::size_t>(order_[static_cast<std::size_t>(i)])];
        n.lo[k] = n.lo[k].cwiseMin(b.lo);
        n.hi[k] = n.hi[k].cwiseMax(b.hi);
      }
    }
  }
}

// Branch and bound: each child's box distance is taken at its parent, and the nearer child is
// searched first (the left on a tie); a child no nearer than the best face so far is passed over.
int FaceBoxTree::nearest(const TriMesh& mesh, const Eigen::Vector3d& p, Eigen::Vector3d& point) const {
  if (nodes_.empty()) return -1;
  struct Entry {
    int child, count;
    double d;
  };
  int best = -1;
  double bestD = std::numeric_limits<double>::infinity();
  Entry stack[128];
  int top = 0;
  auto pushChildren = [&](const Node& n) {
    const double dl = boxDistance2(n.lo[0], n.hi[0], p), dr = boxDistance2(n.lo[1], n.hi[1], p);
    const int nearer = dl <= dr ? 0 : 1;
    stack[top++] = {n.child[1 - nearer], n.count[1 - nearer], nearer == 0 ? dr : dl};
    stack[top++] = {n.child[nearer], n.count[nearer], nearer == 0 ? dl : dr};
  };
  pushChildren(nodes_[0]);
  while (top > 0) {
    const Entry e = stack[--top];
    if (e.d >= bestD) continue;
    if (e.child >= 0) {
      pushChildren(nodes_[static_cast<std::size_t>(e.child)]);
      continue;
    }
    for (int i = -e.child - 1, end = i + e.count; i < end; ++i) {
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
  }
  return best;
}

}  // namespace virtual_tryon
