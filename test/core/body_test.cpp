// Body: derived data is built lazily, once, and only what is asked for.
#include "virtual_tryon/core/body/body.h"
#include "virtual_tryon/core/scenes/procedural.h"

#include <gtest/gtest.h>

#include <thread>
#include <vector>

namespace vt = virtual_tryon;

TEST(Body, BuildsNothingHeavyUntilAsked) {
  const vt::Body body(vt::makeSphere(0.3));
  EXPECT_FALSE(body.bvhBuilt());
  EXPECT_EQ(body.depthMapRenders(), 0);
  EXPECT_TRUE(body.closed());  // the topology summary is kept from construction,
  EXPECT_TRUE(body.adjacencyBuilt());  // and the edge list it was counted over
}

TEST(Body, EdgeNormalsAreBuiltOnceOnFirstUseFromManyThreads) {
  const vt::TriMesh sphere = vt::makeSphere(0.3);
  const vt::Body body(sphere);
  std::vector<const vt::MatrixX3d*> seen(4, nullptr);
  std::vector<std::thread> threads;
  for (int t = 0; t < 4; ++t) threads.emplace_back([&, t] { seen[t] = &body.edgeNormals(); });
  for (auto& th : threads) th.join();
  for (const auto* p : seen) EXPECT_EQ(p, seen[0]);
  // Each row as edgeNormal(e) computes it, and the vertex normals as mesh.h's.
  for (Eigen::Index e = 0; e < body.edges().rows(); ++e)
    EXPECT_EQ(body.edgeNormals().row(e), body.edgeNormal(static_cast<int>(e)).transpose());
  EXPECT_EQ(body.vertexNormals(), vt::vertexNormals(sphere));
  EXPECT_EQ(body.edges(), vt::uniqueEdges(sphere));
  EXPECT_EQ(body.faceEdges().rows(), sphere.numFaces());
  EXPECT_EQ(body.edgeNormals().rows(), body.edges().rows());
  // A closed sphere: E = 3F/2, and every edge normal has unit length and points outward.
  EXPECT_EQ(body.edges().rows() * 2, sphere.numFaces() * 3);
  for (Eigen::Index e = 0; e < body.edges().rows(); ++e) {
    const Eigen::Vector3d mid =
        0.5 * (sphere.V.row(body.edges()(e, 0)) + sphere.V.row(body.edges()(e, 1))).transpose();
    EXPECT_NEAR(body.edgeNormals().row(e).norm(), 1.0, 1e-12);
    EXPECT_GT(body.edgeNormals().row(e).dot(mid.normalized()), 0.9);
  }
  EXPECT_FALSE(body.bvhBuilt());
}
