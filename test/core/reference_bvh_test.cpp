// The accelerated referee (reference_bvh.h) must count exactly what the brute-force referee
// (reference_check.h) counts: same predicates, candidates from its own trees.
#include "virtual_tryon/core/resolve/penetration_resolver.h"
#include "virtual_tryon/core/scenes/procedural.h"
#include "virtual_tryon/testing/reference_bvh.h"
#include "virtual_tryon/testing/reference_check.h"

#include <gtest/gtest.h>

#include <random>

using namespace virtual_tryon;
using V3 = Eigen::Vector3d;

namespace {

void expectSame(const TriMesh& body, const TriMesh& garment, bool inside = true) {
  const ReferenceCounts a = referenceCounts(body, garment, inside);
  const ReferenceCounts b = ReferenceReferee(body).count(garment, inside);
  EXPECT_EQ(a.garment_edge_crossings, b.garment_edge_crossings);
  EXPECT_EQ(a.body_edge_crossings, b.body_edge_crossings);
  EXPECT_EQ(a.vertices_inside, b.vertices_inside);
  EXPECT_NEAR(a.max_depth, b.max_depth, 1e-12);
}

}  // namespace

TEST(ReferenceBvh, CountsEqualTheBruteForceReferee) {
  const ResolveScene s = makeWrinkledTubeScene(48, 30);
  expectSame(s.body, s.garment);
  const TriMesh sphere = makeSphere(0.1, V3::Zero(), 4);
  expectSame(sphere, makePatch(0.12, 0.12, 24, 24, V3(0.003, 0.08, -0.002)));
  // Half resolved: crossings in both directions, some vertices still inside.
  TriMesh g = s.garment;
  Body b(s.body);
  ResolverParams p;
  p.max_iterations = 1;
  resolvePenetrations(b, g, p);
  expectSame(s.body, g);
  // Random jitter, an open body (no inside count), a garment far away.
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-0.01, 0.01);
  TriMesh j = s.garment;
  for (Eigen::Index i = 0; i < j.V.rows(); ++i)
    for (int k = 0; k < 3; ++k) j.V(i, k) += u(rng);
  expectSame(s.body, j);
  expectSame(makeCylinder(0.1, 0.4, V3::Zero(), 32, 8, false), makePatch(0.1, 0.1, 10, 10, V3(0.1, 0, 0)), false);
  expectSame(sphere, makePatch(0.1, 0.1, 4, 4, V3(0, 1, 0)));
}

TEST(ReferenceBvh, DepthIsTheDistanceToTheSurface) {
  const TriMesh sphere = makeSphere(0.2, V3::Zero(), 5);
  TriMesh pts;
  pts.V.resize(3, 3);
  pts.V << 0, 0, 0, 0.1, 0, 0, 0.3, 0, 0;
  ReferenceReferee r(sphere);
  std::vector<char> in;
  std::vector<double> depth;
  r.inside(pts, in, &depth);
  EXPECT_EQ(in, (std::vector<char>{1, 1, 0}));
  EXPECT_NEAR(depth[0], 0.2, 2e-3);  // a tessellated sphere is a little smaller
  EXPECT_NEAR(depth[1], 0.1, 2e-3);
  EXPECT_TRUE(std::isnan(depth[2]));
  const std::vector<double> sd = r.signedDistances(pts);
  EXPECT_NEAR(sd[0], -depth[0], 1e-15);
  EXPECT_NEAR(sd[1], -depth[1], 1e-15);
  EXPECT_NEAR(sd[2], 0.1, 2e-3);
}
