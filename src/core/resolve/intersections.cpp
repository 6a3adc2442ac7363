#include "virtual_tryon/core/resolve/intersections.h"

#include "virtual_tryon/core/geometry/edge_face_crossing.h"

#include "core/geometry/fcl_bvh.h"

#include <fcl/narrowphase/collision.h>
#include <fcl/narrowphase/detail/traversal/collision/mesh_collision_traversal_node.h>
#include <fcl/narrowphase/detail/traversal/collision_node.h>

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

void detectCrossings(const Body& body, const TriMesh& garment, const GarmentTopology& topo,
                     CrossingSet& out, const std::vector<int>* faces) {
  out.garment_edges.clear();
  out.body_edges.clear();
  if (garment.F.rows() == 0 || body.mesh().F.rows() == 0) return;
  if (faces && faces->empty()) return;

  const BodyBVH& bvh = body.bvh();
  auto gModel = buildFclModel<FclModel>(garment.V, garment.F, faces);

  fcl::CollisionRequestd request(std::numeric_limits<std::size_t>::max() / 2, false);
  fcl::CollisionResultd result;
  // fcl::collide copies both AABB models on every call (its BVHCollideImpl), so each detection
  // would cost O(body size) however few garment faces it tests. The traversal itself reads the
  // models and, with identity transforms, leaves them as they are.
  fcl::detail::MeshCollisionTraversalNode<fcl::AABBd> node;
  fcl::Transform3d tfBody = fcl::Transform3d::Identity(), tfGarment = fcl::Transform3d::Identity();
  if (!fcl::detail::initialize(node, *bvh.model, tfBody, *gModel, tfGarment, request, result)) return;
  fcl::detail::collide(&node);
  std::vector<fcl::Contactd> contacts;
  result.getContacts(contacts);

  const MatrixX3d& BV = body.mesh().V;
  const MatrixX3i& BF = body.mesh().F;
  const MatrixX2i& BE = body.edges();
  const MatrixX3i& BFE = body.faceEdges();
  const MatrixX3d& GV = garment.V;
  const MatrixX3i& GF = garment.F;

  EdgeFaceHit hit;
  for (const fcl::Contactd& c : contacts) {
    const int bf = c.b1;
    const int gf = faces ? (*faces)[static_cast<std::size_t>(c.b2)] : c.b2;
    const Eigen::Vector3d y0 = row(BV, BF(bf, 0)), y1 = row(BV, BF(bf, 1)), y2 = row(BV, BF(bf, 2));
    const Eigen::Vector3d x0 = row(GV, GF(gf, 0)), x1 = row(GV, GF(gf, 1)), x2 = row(GV, GF(gf, 2));
    for (int k = 0; k < 3; ++k) {
      const int ge = topo.face_edges(gf, k);
      const Eigen::Vector3d a = row(GV, topo.edges(ge, 0)), b = row(GV, topo.edges(ge, 1));
      if (segmentCrossesTriangle(a, b, y0, y1, y2, &hit))
        out.garment_edges.push_back({ge, bf, hit.t, hit.bary, hit.sa, hit.sb});
      const int be = BFE(bf, k);
      const Eigen::Vector3d p = row(BV, BE(be, 0)), q = row(BV, BE(be, 1));
      if (segmentCrossesTriangle(p, q, x0, x1, x2, &hit))
        out.body_edges.push_back({be, gf, hit.t, hit.bary, hit.sa, hit.sb});
    }
  }
  sortUnique(out.garment_edges);
  sortUnique(out.body_edges);
}

}  // namespace virtual_tryon
