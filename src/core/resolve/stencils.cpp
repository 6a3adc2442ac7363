#include "virtual_tryon/core/resolve/stencils.h"

#include <algorithm>
#include <map>
#include <utility>

namespace virtual_tryon {

std::vector<Stencil> buildStencils(const Body& body, const TriMesh& garment,
                                   const GarmentTopology& topo, const CrossingSet& crossings,
                                   std::vector<int>* illegal) {
  std::vector<Stencil> out;
  out.reserve(crossings.size());
  // Vertex-face stencils, merged per (illegal vertex, body face): D depends on nothing else.
  std::map<std::pair<int, int>, std::size_t> seen;
  if (illegal) illegal->clear();
  for (const EdgeFaceCrossing& c : crossings.garment_edges) {
    const bool firstBehind = c.s0 < c.s1;  // by the crossing convention exactly one is behind
    const int x0 = topo.edges(c.edge, firstBehind ? 0 : 1);
    const double D = firstBehind ? c.s0 : c.s1;
    if (!seen.emplace(std::make_pair(x0, c.face), out.size()).second) continue;
    Stencil s;
    s.count = 1;
    s.vertex = {{x0, -1, -1}};
    s.weight = {{1.0, 0.0, 0.0}};
    s.normal = body.faceNormal(c.face);
    s.D = D;
    out.push_back(s);
    if (illegal) illegal->push_back(x0);
  }
  // Face stencils from body edges crossing garment faces.
  const MatrixX3d& BV = body.mesh().V;
  for (const EdgeFaceCrossing& c : crossings.body_edges) {
    const Eigen::Vector3d n = body.edgeNormal(c.edge);
    if (n.squaredNorm() == 0) continue;
    const Eigen::Vector3d y0 = BV.row(body.edges()(c.edge, 0)).transpose();
    const Eigen::Vector3d y1 = BV.row(body.edges()(c.edge, 1)).transpose();
    const Eigen::Vector3d p = y0 + c.t * (y1 - y0);
    Stencil s;
    s.count = 3;
    Eigen::Vector3d cpt = Eigen::Vector3d::Zero();
    for (int k = 0; k < 3; ++k) {
      s.vertex[k] = garment.F(c.face, k);
      s.weight[k] = c.bary[k];
      cpt += c.bary[k] * garment.V.row(s.vertex[k]).transpose();
    }
    s.normal = n;
    s.D = n.dot(cpt - p);
    out.push_back(s);
  }
  if (illegal) {
    std::sort(illegal->begin(), illegal->end());
    illegal->erase(std::unique(illegal->begin(), illegal->end()), illegal->end());
  }
  return out;
}

}  // namespace virtual_tryon
