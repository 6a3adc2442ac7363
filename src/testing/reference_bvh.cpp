#include "virtual_tryon/testing/reference_bvh.h"

#include "testing/reference_predicates.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>

namespace virtual_tryon {
namespace {

// The predicates of reference_check.cpp (a unit test compares the counts).
using reference_predicates::mtHit;
using reference_predicates::pointTriangleDistance;

Eigen::Vector3d corner(const TriMesh& m, Eigen::Index f, int k) { return m.V.row(m.F(f, k)).transpose(); }

// Crossings of the edges of `edgesOf` with the faces of `facesOf` (tree over facesOf).
std::size_t countCrossings(const TriMesh& edgesOf, const MatrixX2i& E, const TriMesh& facesOf,
                           const ReferenceTree& tree, double eps) {
  std::size_t n = 0;
  for (Eigen::Index e = 0; e < E.rows(); ++e) {
    const Eigen::Vector3d a = edgesOf.V.row(E(e, 0)).transpose(), b = edgesOf.V.row(E(e, 1)).transpose();
    tree.overlapping(a.cwiseMin(b), a.cwiseMax(b), [&](int f) {
      if (mtHit(a, b - a, corner(facesOf, f, 0), corner(facesOf, f, 1), corner(facesOf, f, 2), eps)) ++n;
    });
  }
  return n;
}

}  // namespace

ReferenceTree::ReferenceTree(const TriMesh& mesh) {
  const int nf = static_cast<int>(mesh.F.rows());
  if (nf == 0) return;
  face_lo_.resize(static_cast<std::size_t>(nf));
  face_hi_.resize(static_cast<std::size_t>(nf));
  std::vector<Eigen::Vector3d> centre(static_cast<std::size_t>(nf));
  for (int f = 0; f < nf; ++f) {
    face_lo_[f] = face_hi_[f] = corner(mesh, f, 0);
    for (int k = 1; k < 3; ++k) {
      face_lo_[f] = face_lo_[f].cwiseMin(corner(mesh, f, k));
      face_hi_[f] = face_hi_[f].cwiseMax(corner(mesh, f, k));
    }
    centre[f] = 0.5 * (face_lo_[f] + face_hi_[f]);
  }
  order_.resize(static_cast<std::size_t>(nf));
  std::iota(order_.begin(), order_.end(), 0);
  nodes_.reserve(static_cast<std::size_t>(2 * nf / 4 + 8));
  build(face_lo_, face_hi_, centre, 0, nf);
}

int ReferenceTree::build(const std::vector<Eigen::Vector3d>& lo, const std::vector<Eigen::Vector3d>& hi,
                         const std::vector<Eigen::Vector3d>& centre, int first, int count) {
  const int id = static_cast<int>(nodes_.size());
  nodes_.emplace_back();
  Eigen::Vector3d blo = lo[order_[first]], bhi = hi[order_[first]];
  for (int i = first + 1; i < first + count; ++i) {
    blo = blo.cwiseMin(lo[order_[i]]);
    bhi = bhi.cwiseMax(hi[order_[i]]);
  }
  nodes_[id].lo = blo;
  nodes_[id].hi = bhi;
  if (count <= 4) {
    nodes_[id].first = first;
    nodes_[id].count = count;
    return id;
  }
  int axis = 0;
  (bhi - blo).maxCoeff(&axis);
  const int mid = first + count / 2;
  std::nth_element(order_.begin() + first, order_.begin() + mid, order_.begin() + first + count,
                   [&](int a, int b) { return centre[a][axis] < centre[b][axis]; });
  const int left = build(lo, hi, centre, first, mid - first);
  const int right = build(lo, hi, centre, mid, first + count - mid);
  nodes_[id].left = left;
  nodes_[id].right = right;
  return id;
}

double ReferenceTree::distance(const TriMesh& mesh, const Eigen::Vector3d& p) const {
  double best = std::numeric_limits<double>::infinity();
  if (nodes_.empty()) return best;
  auto boxDistance = [&](const Node& n) {
    const Eigen::Vector3d q = p.cwiseMax(n.lo).cwiseMin(n.hi);
    return (p - q).norm();
  };
  // Median splits: the depth is about log2(faces / 4), and the stack holds one entry per level
  // plus one (as in overlapping and alongSegment).
  std::pair<double, int> stack[128];
  int top = 0;
  stack[top++] = {boxDistance(nodes_[0]), 0};
  while (top > 0) {
    const auto [bd, id] = stack[--top];
    if (bd > best) continue;
    const Node& n = nodes_[id];
    if (n.left < 0) {
      for (int i = n.first; i < n.first + n.count; ++i) {
        const int f = order_[i];
        best = std::min(best, pointTriangleDistance(p, corner(mesh, f, 0), corner(mesh, f, 1), corner(mesh, f, 2)));
      }
      continue;
    }
    const double dl = boxDistance(nodes_[n.left]), dr = boxDistance(nodes_[n.right]);
    // Nearer child last, so it is visited first.
    if (dl < dr) {
      stack[top++] = {dr, n.right};
      stack[top++] = {dl, n.left};
    } else {
      stack[top++] = {dl, n.left};
      stack[top++] = {dr, n.right};
    }
  }
  return best;
}

ReferenceReferee::ReferenceReferee(const TriMesh& body) : body_(body), tree_(body) {
  body_edges_ = uniqueEdges(body_);
  boundingBox(body_, lo_, hi_);
}

void ReferenceReferee::inside(const TriMesh& garment, std::vector<char>& inside, std::vector<double>* depth) const {
  inside.assign(static_cast<std::size_t>(garment.V.rows()), 0);
  if (depth) depth->assign(inside.size(), std::numeric_limits<double>::quiet_NaN());
  if (body_.F.rows() == 0) return;
  const double L = reference_predicates::insideRayLength(lo_, hi_);
  const auto& dirs = reference_predicates::kInsideRayDirections;
  for (Eigen::Index v = 0; v < garment.V.rows(); ++v) {
    const Eigen::Vector3d p = garment.V.row(v).transpose();
    if ((p.array() < lo_.array()).any() || (p.array() > hi_.array()).any()) continue;
    int votes = 0;
    for (const auto& d : dirs) {
      int hits = 0;
      const Eigen::Vector3d seg = L * d;
      tree_.alongSegment(p, seg, [&](int f) {
        if (mtHit(p, seg, corner(body_, f, 0), corner(body_, f, 1), corner(body_, f, 2), 0.0)) ++hits;
      });
      votes += hits & 1;
    }
    if (votes < 2) continue;
    inside[v] = 1;
    if (depth) (*depth)[v] = tree_.distance(body_, p);
  }
}

std::vector<double> ReferenceReferee::signedDistances(const TriMesh& garment) const {
  std::vector<char> in;
  std::vector<double> d;
  inside(garment, in, &d);
  for (std::size_t v = 0; v < in.size(); ++v)
    d[v] = in[v] ? -d[v] : tree_.distance(body_, garment.V.row(static_cast<Eigen::Index>(v)).transpose());
  return d;
}

ReferenceCounts ReferenceReferee::count(const TriMesh& garment, bool countInside, double eps) const {
  ReferenceCounts r;
  r.boundary_loops = referenceBoundaryLoops(garment);
  r.garment_edge_crossings = countCrossings(garment, uniqueEdges(garment), body_, tree_, eps);
  const ReferenceTree garmentTree(garment);
  r.body_edge_crossings = countCrossings(body_, body_edges_, garment, garmentTree, eps);
  if (!countInside) return r;
  std::vector<char> in;
  std::vector<double> depth;
  inside(garment, in, &depth);
  for (std::size_t v = 0; v < in.size(); ++v)
    if (in[v]) {
      ++r.vertices_inside;
      r.max_depth = std::max(r.max_depth, depth[v]);
    }
  return r;
}

}  // namespace virtual_tryon
