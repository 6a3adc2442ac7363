// Stencil gradients against finite differences, swept over degenerate configurations (in the
// manner of ipc-toolkit's derivative tests): a garment edge through a body face at its middle,
// next to one of its edges, next to a corner, nearly parallel to it (grazing), nearly
// perpendicular, very short and very long; and body edges through garment faces near a corner
// and along an edge.
//
// A vertex-face stencil says D(x) = n . (x0 - p): the illegal vertex's signed distance to the
// crossed body face's plane, gradient n on x0. Here D is measured again from the geometry (a new
// detection at x0 +- h e_k) and its central difference must equal the stencil's gradient. A face
// stencil is linear by construction (fixed barycentric weights w and crossing point p), so its
// gradient w_i n_e is checked as the linearisation of the garment point over p: the weights are
// the crossing's barycentric coordinates (they sum to 1 and reproduce p), n_e is unit, D = 0.
#include "virtual_tryon/core/body/body.h"
#include "virtual_tryon/core/resolve/intersections.h"
#include "virtual_tryon/core/resolve/stencils.h"

#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

using namespace virtual_tryon;

namespace {

// A body of two triangles (a unit square in the x-y plane at z = 0, normal +z).
TriMesh squareBody() {
  TriMesh m;
  m.V.resize(4, 3);
  m.V << 0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0;
  m.F.resize(2, 3);
  m.F << 0, 1, 2, 0, 2, 3;
  return m;
}

// A garment of one triangle with the first edge (a, b) and a third vertex c.
TriMesh triangle(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& c) {
  TriMesh m;
  m.V.resize(3, 3);
  m.V.row(0) = a.transpose();
  m.V.row(1) = b.transpose();
  m.V.row(2) = c.transpose();
  m.F.resize(1, 3);
  m.F << 0, 1, 2;
  return m;
}

// The D of the vertex-face stencil of vertex v and body face f, measured again; NaN if gone.
double vertexFaceD(const Body& body, const TriMesh& garment, int v, int f) {
  const GarmentTopology topo(garment);
  CrossingSet cs;
  detectCrossings(body, garment, topo, cs);
  for (const Stencil& s : buildStencils(body, garment, topo, cs))
    if (s.count == 1 && s.vertex[0] == v && s.normal.isApprox(body.faceNormals().row(f).transpose())) return s.D;
  return std::nan("");
}

struct Config {
  std::string name;
  Eigen::Vector3d a, b;  // the garment edge; a is behind the body (z < 0)
};

std::vector<Config> edgeConfigs() {
  return {
      {"through the middle", {0.3, 0.4, -0.2}, {0.35, 0.45, 0.3}},
      {"next to a face edge", {0.5, 1e-7, -0.1}, {0.5, 2e-7, 0.2}},
      {"next to the diagonal", {0.5, 0.5 + 1e-8, -0.1}, {0.5, 0.5 + 1e-8, 0.1}},
      {"next to a corner", {1 - 1e-7, 1e-7, -0.1}, {1 - 1e-7, 1e-7, 0.1}},
      {"grazing", {0.2, 0.5, -1e-4}, {0.8, 0.5, 2e-4}},
      {"perpendicular, short", {0.4, 0.3, -1e-5}, {0.4, 0.3, 1e-5}},
      {"long", {0.45, 0.2, -50}, {0.55, 0.3, 40}},
  };
}

}  // namespace

TEST(StencilGradients, VertexFaceGradientMatchesFiniteDifferences) {
  const Body body(squareBody());
  for (const Config& c : edgeConfigs()) {
    SCOPED_TRACE(c.name);
    const TriMesh g = triangle(c.a, c.b, c.b + Eigen::Vector3d(0.0, 0.0, 1.0));
    const GarmentTopology topo(g);
    CrossingSet cs;
    detectCrossings(body, g, topo, cs);
    const std::vector<Stencil> stencils = buildStencils(body, g, topo, cs);
    ASSERT_FALSE(stencils.empty());
    int checked = 0;
    for (const Stencil& s : stencils) {
      if (s.count != 1) continue;
      EXPECT_EQ(s.vertex[0], 0);  // the end behind the face
      EXPECT_NEAR(s.normal.norm(), 1.0, 1e-12);
      EXPECT_LT(s.D, 0);
      const int f = s.normal.isApprox(body.faceNormals().row(0).transpose()) ? 0 : 1;
      // h small against the distance to the face and to the face's edges, large against rounding.
      const double h = std::max(1e-9, 1e-3 * std::abs(s.D));
      for (int k = 0; k < 3; ++k) {
        TriMesh plus = g, minus = g;
        plus.V(0, k) += h;
        minus.V(0, k) -= h;
        const double dp = vertexFaceD(body, plus, 0, f), dm = vertexFaceD(body, minus, 0, f);
        if (std::isnan(dp) || std::isnan(dm)) continue;  // the step left the face: no difference
        const double fd = (dp - dm) / (2 * h);
        EXPECT_NEAR(fd, s.normal[k] * s.weight[0], 1e-6) << "axis " << k;
        ++checked;
      }
    }
    EXPECT_GT(checked, 0);
  }
}

TEST(StencilGradients, FaceStencilIsTheLinearisationAtTheCrossingPoint) {
  // The body square's edges poke through a garment triangle standing across them.
  const Body body(squareBody());
  const std::vector<std::pair<std::string, TriMesh>> garments = {
      {"across the diagonal", triangle({0.6, 0.4, -0.3}, {0.4, 0.6, -0.3}, {0.5, 0.5, 0.4})},
      {"across a boundary edge near a corner", triangle({1e-6, -0.2, -0.2}, {1e-6, 0.2, -0.2}, {1e-6, 0.0, 0.3})},
      {"across the diagonal near its end", triangle({0.011, 0.009, -0.1}, {0.009, 0.011, -0.1}, {0.01, 0.01, 0.2})},
  };
  for (const auto& [name, g] : garments) {
    SCOPED_TRACE(name);
    const GarmentTopology topo(g);
    CrossingSet cs;
    detectCrossings(body, g, topo, cs);
    int faceStencils = 0;
    for (const EdgeFaceCrossing& c : cs.body_edges) {
      const Eigen::Vector3d y0 = body.mesh().V.row(body.edges()(c.edge, 0)).transpose();
      const Eigen::Vector3d y1 = body.mesh().V.row(body.edges()(c.edge, 1)).transpose();
      const Eigen::Vector3d p = y0 + c.t * (y1 - y0);
      Eigen::Vector3d at = Eigen::Vector3d::Zero();
      for (int k = 0; k < 3; ++k) at += c.bary[k] * g.V.row(g.F(c.face, k)).transpose();
      EXPECT_NEAR((at - p).norm(), 0.0, 1e-12);
      EXPECT_NEAR(c.bary.sum(), 1.0, 1e-12);
    }
    for (const Stencil& s : buildStencils(body, g, topo, cs)) {
      if (s.count != 3) continue;
      ++faceStencils;
      EXPECT_NEAR(s.normal.norm(), 1.0, 1e-12);
      EXPECT_NEAR(s.weight[0] + s.weight[1] + s.weight[2], 1.0, 1e-12);
      EXPECT_NEAR(s.D, 0.0, 1e-12);
      // The stencil's vertices are the crossed face's, in its order.
      bool matches = false;
      for (const EdgeFaceCrossing& c : cs.body_edges)
        matches = matches || (s.vertex[0] == g.F(c.face, 0) && s.vertex[1] == g.F(c.face, 1) &&
                              s.vertex[2] == g.F(c.face, 2) && std::abs(s.weight[1] - c.bary[1]) < 1e-15);
      EXPECT_TRUE(matches);
    }
    EXPECT_GT(faceStencils, 0);
  }
}
