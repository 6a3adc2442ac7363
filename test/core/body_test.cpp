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
  EXPECT_FALSE(body.adjacencyBuilt());
  EXPECT_EQ(body.depthMapRenders(), 0);
  EXPECT_TRUE(body.closed());  // the topology summary is kept from construction
}

TEST(Body, AdjacencyIsBuiltOnceOnFirstUseFromManyThreads) {
  const vt::TriMesh sphere = vt::makeSphere(0.3);
  const vt::Body body(sphere);
  std::vector<const vt::MatrixX2i*> seen(4, nullptr);
  std::vector<std::thread> threads;
  for (int t = 0; t < 4; ++t) threads.emplace_back([&, t] { seen[t] = &body.edges(); });
  for (auto& th : threads) th.join();
  EXPECT_TRUE(body.adjacencyBuilt());
  for (const auto* p : seen) EXPECT_EQ(p, seen[0]);
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
