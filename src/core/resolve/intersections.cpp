#include "virtual_tryon/core/resolve/intersections.h"

#include "virtual_tryon/core/geometry/edge_face_crossing.h"

#include "core/geometry/fcl_bvh.h"


#include <algorithm>
#include <chrono>
#include <limits>
#include <memory>
#include <tuple>

namespace virtual_tryon {

namespace {

Eigen::Vector3d row(const MatrixX3d& V, int i) { return V.row(i).transpose(); }

bool sameKey(const EdgeFaceCrossing& a, const EdgeFaceCrossing& b) {
  return a.edge == b.edge && a.face == b.face;
}
bool lessKey(const EdgeFaceCrossing& a, const EdgeFaceCrossing& b) {
  return std::tie(a.edge, a.face) < std::tie(b.edge, b.face);
}
void sortUnique(std::vector<EdgeFaceCrossing>& v) {
  std::sort(v.begin(), v.end(), lessKey);
  v.erase(std::unique(v.begin(), v.end(), sameKey), v.end());
}

}  // namespace

GarmentTopology::GarmentTopology(const TriMesh& garment) { edges = uniqueEdges(garment, &face_edges); }

const FaceBoxTree& BodyBVH::faceTree(const TriMesh& mesh) const {
  std::call_once(tree_once_, [&] { tree_ = std::make_unique<FaceBoxTree>(mesh); });
  return *tree_;
}

namespace {

// The crossings of garment face gf's three edges with body face bf, and of bf's three edges with gf.
void testFacePair(const Body& body, const TriMesh& garment, const GarmentTopology& topo, int bf, int gf,
                  CrossingSet& out) {
  const MatrixX3d& BV = body.mesh().V;
  const MatrixX3i& BF = body.mesh().F;
  const MatrixX2i& BE = body.edges();
  const MatrixX3i& BFE = body.faceEdges();
  const MatrixX3d& GV = garment.V;
  const MatrixX3i& GF = garment.F;
  const Eigen::Vector3d y0 = row(BV, BF(bf, 0)), y1 = row(BV, BF(bf, 1)), y2 = row(BV, BF(bf, 2));
  const Eigen::Vector3d x0 = row(GV, GF(gf, 0)), x1 = row(GV, GF(gf, 1)), x2 = row(GV, GF(gf, 2));
  EdgeFaceHit hit;
  for (int k = 0; k < 3; ++k) {
    const int ge = topo.face_edges(gf, k);
    const Eigen::Vector3d a = row(GV, topo.edges(ge, 0)), b = row(GV, topo.edges(ge, 1));
    if (segmentCrossesTriangle(a, b, y0, y1, y2, &hit)) out.garment_edges.push_back({ge, bf, hit.t, hit.bary, hit.sa, hit.sb});
    const int be = BFE(bf, k);
    const Eigen::Vector3d p = row(BV, BE(be, 0)), q = row(BV, BE(be, 1));
    if (segmentCrossesTriangle(p, q, x0, x1, x2, &hit)) out.body_edges.push_back({be, gf, hit.t, hit.bary, hit.sa, hit.sb});
  }
}

}  // namespace

// Candidate pairs are the (body face, garment face) pairs whose bounding boxes overlap, from the
// body's box tree (built once with the body) and one box query per garment face; every crossing
// lies in such a pair, and the segment tests decide.
void detectCrossings(const Body& body, const TriMesh& garment, const GarmentTopology& topo,
                     CrossingSet& out, const std::vector<int>* faces) {
  out.garment_edges.clear();
  out.body_edges.clear();
  if (garment.F.rows() == 0 || body.mesh().F.rows() == 0) return;
  if (faces && faces->empty()) return;
  const FaceBoxTree& tree = body.bvh().faceTree(body.mesh());
  const MatrixX3d& GV = garment.V;
  const MatrixX3i& GF = garment.F;
  const int n = faces ? static_cast<int>(faces->size()) : static_cast<int>(GF.rows());
  for (int i = 0; i < n; ++i) {
    const int gf = faces ? (*faces)[static_cast<std::size_t>(i)] : i;
    Eigen::Vector3d lo = row(GV, GF(gf, 0)), hi = lo;
    for (int k = 1; k < 3; ++k) {
      lo = lo.cwiseMin(row(GV, GF(gf, k)));
      hi = hi.cwiseMax(row(GV, GF(gf, k)));
    }
    tree.overlapping(lo, hi, [&](int bf) { testFacePair(body, garment, topo, bf, gf, out); });
  }
  sortUnique(out.garment_edges);
  sortUnique(out.body_edges);
}

}  // namespace virtual_tryon
