#include "virtual_tryon/testing/reference_check.h"

#include "virtual_tryon/core/io/json_object.h"

#include "testing/reference_predicates.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <set>
#include <utility>
#include <vector>

namespace virtual_tryon {
namespace {

struct Box {
  Eigen::Vector3d lo, hi;
  bool overlaps(const Box& o) const {
    return (lo.array() <= o.hi.array()).all() && (o.lo.array() <= hi.array()).all();
  }
};

// Moller-Trumbore: does segment o + t dir, t in (eps, 1 - eps), hit the triangle (u, v > 0)?
using reference_predicates::mtHit;
using reference_predicates::pointTriangleDistance;

std::vector<Box> faceBoxes(const TriMesh& m) {
  std::vector<Box> boxes(static_cast<std::size_t>(m.F.rows()));
  for (Eigen::Index f = 0; f < m.F.rows(); ++f) {
    Box& bx = boxes[static_cast<std::size_t>(f)];
    bx.lo = bx.hi = m.V.row(m.F(f, 0)).transpose();
    for (int k = 1; k < 3; ++k) {
      bx.lo = bx.lo.cwiseMin(m.V.row(m.F(f, k)).transpose());
      bx.hi = bx.hi.cwiseMax(m.V.row(m.F(f, k)).transpose());
    }
  }
  return boxes;
}

std::size_t countEdgeCrossings(const TriMesh& edgesOf, const TriMesh& facesOf, double eps) {
  const MatrixX2i E = uniqueEdges(edgesOf);
  const std::vector<Box> boxes = faceBoxes(facesOf);
  std::size_t n = 0;
  for (Eigen::Index e = 0; e < E.rows(); ++e) {
    const Eigen::Vector3d a = edgesOf.V.row(E(e, 0)).transpose(), b = edgesOf.V.row(E(e, 1)).transpose();
    const Box eb{a.cwiseMin(b), a.cwiseMax(b)};
    for (Eigen::Index f = 0; f < facesOf.F.rows(); ++f) {
      if (!eb.overlaps(boxes[static_cast<std::size_t>(f)])) continue;
      if (mtHit(a, b - a, facesOf.V.row(facesOf.F(f, 0)).transpose(), facesOf.V.row(facesOf.F(f, 1)).transpose(),
                facesOf.V.row(facesOf.F(f, 2)).transpose(), eps))
        ++n;
    }
  }
  return n;
}

}  // namespace

ReferenceCounts referenceCounts(const TriMesh& body, const TriMesh& garment, bool countInside,
                                double eps) {
  ReferenceCounts r;
  r.boundary_loops = referenceBoundaryLoops(garment);
  r.garment_edge_crossings = countEdgeCrossings(garment, body, eps);
  r.body_edge_crossings = countEdgeCrossings(body, garment, eps);
  if (!countInside) return r;
  Eigen::Vector3d lo, hi;
  boundingBox(body, lo, hi);
  const double L = reference_predicates::insideRayLength(lo, hi);
  const auto& dirs = reference_predicates::kInsideRayDirections;
  for (Eigen::Index v = 0; v < garment.V.rows(); ++v) {
    const Eigen::Vector3d p = garment.V.row(v).transpose();
    if ((p.array() < lo.array()).any() || (p.array() > hi.array()).any()) continue;
    int votes = 0;
    for (const auto& d : dirs) {
      int hits = 0;
      for (Eigen::Index f = 0; f < body.F.rows(); ++f)
        if (mtHit(p, L * d, body.V.row(body.F(f, 0)).transpose(), body.V.row(body.F(f, 1)).transpose(),
                  body.V.row(body.F(f, 2)).transpose(), 0.0))
          ++hits;
      votes += hits & 1;
    }
    if (votes < 2) continue;
    ++r.vertices_inside;
    double dmin = std::numeric_limits<double>::infinity();
    for (Eigen::Index f = 0; f < body.F.rows(); ++f)
      dmin = std::min(dmin, pointTriangleDistance(p, body.V.row(body.F(f, 0)).transpose(),
                                                  body.V.row(body.F(f, 1)).transpose(),
                                                  body.V.row(body.F(f, 2)).transpose()));
    r.max_depth = std::max(r.max_depth, dmin);
  }
  return r;
}

std::size_t referenceBoundaryLoops(const TriMesh& garment) {
  std::map<std::pair<int, int>, int> uses;
  for (Eigen::Index f = 0; f < garment.F.rows(); ++f)
    for (int k = 0; k < 3; ++k) {
      const int a = garment.F(f, k), b = garment.F(f, (k + 1) % 3);
      ++uses[{std::min(a, b), std::max(a, b)}];
    }
  std::map<int, std::vector<int>> next;  // boundary neighbours of each boundary vertex
  for (const auto& u : uses)
    if (u.second == 1) {
      next[u.first.first].push_back(u.first.second);
      next[u.first.second].push_back(u.first.first);
    }
  std::set<int> seen;
  std::size_t loops = 0;
  for (const auto& start : next) {
    if (seen.count(start.first)) continue;
    ++loops;
    std::vector<int> stack{start.first};
    seen.insert(start.first);
    while (!stack.empty()) {
      const int v = stack.back();
      stack.pop_back();
      for (int w : next[v])
        if (seen.insert(w).second) stack.push_back(w);
    }
  }
  return loops;
}

std::string toJson(const ReferenceCounts& c) {
  return json::Obj()
      .add("garment_edge_crossings", c.garment_edge_crossings)
      .add("body_edge_crossings", c.body_edge_crossings)
      .add("vertices_inside", c.vertices_inside)
      .add("max_depth_m", c.max_depth)
      .add("boundary_loops", c.boundary_loops)
      .str();
}

}  // namespace virtual_tryon
