// A body that moves: a new frame reuses the topology and refits the face trees, and answers every
// query as a body built from scratch on the same vertices does.
#include "virtual_tryon/core/body/body.h"
#include "virtual_tryon/core/geometry/point_queries.h"
#include "virtual_tryon/core/resolve/penetration_resolver.h"
#include "virtual_tryon/core/scenes/procedural.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

using namespace virtual_tryon;

namespace {

// The tube scene's body bent: each vertex turned about z by an angle that grows with its height.
MatrixX3d bent(const MatrixX3d& V, double amount) {
  MatrixX3d W = V;
  for (Eigen::Index i = 0; i < V.rows(); ++i) {
    const double a = amount * V(i, 1);
    W(i, 0) = std::cos(a) * V(i, 0) - std::sin(a) * V(i, 1) * 0.2;
    W(i, 1) = V(i, 1) + std::sin(a) * V(i, 0) * 0.2;
  }
  return W;
}

}  // namespace

TEST(BodyFrame, RefittedTreesAnswerAsFreshOnes) {
  const ResolveScene scene = makeWrinkledTubeScene();
  const Body rest(scene.body);
  rest.bvh();
  const MatrixX3d moved = bent(scene.body.V, 0.8);
  const Body frame(rest, moved);
  EXPECT_TRUE(frame.bvhRefitted());
  EXPECT_TRUE(frame.bvhBuilt());
  const Body fresh(TriMesh{moved, scene.body.F});
  EXPECT_FALSE(fresh.bvhRefitted());
  EXPECT_EQ(frame.closed(), fresh.closed());
  EXPECT_EQ(frame.edges(), fresh.edges());
  EXPECT_TRUE(frame.faceNormals().isApprox(fresh.faceNormals(), 1e-15));
  EXPECT_TRUE(frame.edgeNormals().isApprox(fresh.edgeNormals(), 1e-15));
  EXPECT_TRUE(frame.vertexNormals().isApprox(fresh.vertexNormals(), 1e-15));
  EXPECT_EQ(frame.boxMin(), fresh.boxMin());
  EXPECT_NEAR(frame.meanEdgeLength(), fresh.meanEdgeLength(), 1e-15);
  EXPECT_NEAR(frame.signedVolume(), fresh.signedVolume(), 1e-15);
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  const Eigen::Vector3d c = 0.5 * (fresh.boxMin() + fresh.boxMax()), h = 0.6 * (fresh.boxMax() - fresh.boxMin());
  for (int k = 0; k < 300; ++k) {
    const Eigen::Vector3d p = c + Eigen::Vector3d(u(rng), u(rng), u(rng)).cwiseProduct(h);
    EXPECT_EQ(pointInsideBody(frame, p), pointInsideBody(fresh, p)) << k;
    EXPECT_NEAR(closestPointOnBody(frame, p).distance, closestPointOnBody(fresh, p).distance, 1e-12) << k;
  }
  // Points just off the surface, where a leaf box that missed its face's move would show.
  for (Eigen::Index v = 0; v < moved.rows(); v += std::max<Eigen::Index>(1, moved.rows() / 200))
    for (double off : {-2e-3, 2e-3}) {
      const Eigen::Vector3d p = moved.row(v).transpose() + off * fresh.vertexNormals().row(v).transpose();
      EXPECT_EQ(pointInsideBody(frame, p), pointInsideBody(fresh, p)) << v;
      EXPECT_EQ(pointInsideBody(frame, p), off < 0) << v;
    }
  // The resolver on the moved garment: the same result on both.
  TriMesh g1{bent(scene.garment.V, 0.8), scene.garment.F}, g2 = g1;
  const ResolverReport a = resolvePenetrations(frame, g1), b = resolvePenetrations(fresh, g2);
  EXPECT_EQ(a.garment_edge_crossings_before, b.garment_edge_crossings_before);
  EXPECT_EQ(a.body_edge_crossings_before, b.body_edge_crossings_before);
  EXPECT_EQ(a.converged, b.converged);
  EXPECT_EQ(g1.V, g2.V);
  // Moved from: the same answers again, the trees refitted in place.
  Body first(scene.body);
  first.bvh();
  const Body taken(std::move(first), moved);
  EXPECT_TRUE(taken.bvhRefitted());
  EXPECT_EQ(taken.edges(), fresh.edges());
  TriMesh g3{bent(scene.garment.V, 0.8), scene.garment.F};
  resolvePenetrations(taken, g3);
  EXPECT_EQ(g3.V, g2.V);
  // A frame of another size is refused.
  EXPECT_THROW(Body(rest, MatrixX3d::Zero(3, 3)), std::invalid_argument);
}
