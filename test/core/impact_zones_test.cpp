// Stencils, impact zones and the minimum-displacement solve against closed-form answers.
#include "test_helpers.h"
#include "virtual_tryon/core/resolve/impact_zones.h"
#include "virtual_tryon/core/scenes/procedural.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

using namespace virtual_tryon;
using V3 = Eigen::Vector3d;
using virtual_tryon_test::vertexStencil;

namespace {

V3 displacementOf(const ZoneSolution& sol, int vertex) {
  for (std::size_t i = 0; i < sol.vertices.size(); ++i)
    if (sol.vertices[i] == vertex) return sol.displacement[i];
  return V3::Zero();
}

// g_i . dx for stencil s.
double gradDot(const Stencil& s, const ZoneSolution& sol) {
  double g = 0;
  for (int j = 0; j < s.count; ++j) g += s.weight[j] * s.normal.dot(displacementOf(sol, s.vertex[j]));
  return g;
}

}  // namespace

TEST(ImpactZones, SingleStencilClosedForm) {
  // A vertex 3 mm behind a face with normal +y; clearance 1 mm: lambda = d - D = 4 mm, dx = 4 mm n.
  const std::vector<Stencil> st = {vertexStencil(5, V3(0, 1, 0), -0.003)};
  const ZoneSolution sol = solveImpactZone(st, {0}, 0.001);
  ASSERT_EQ(sol.vertices.size(), 1u);
  EXPECT_EQ(sol.vertices[0], 5);
  EXPECT_NEAR(sol.lambda[0], 0.004, 1e-12);
  EXPECT_NEAR((sol.displacement[0] - V3(0, 0.004, 0)).norm(), 0, 1e-12);
  EXPECT_TRUE(sol.feasible);
}

TEST(ImpactZones, FaceStencilMovesTheThreeVerticesByTheirWeights) {
  // Body edge through a garment face at weights (0.5, 0.3, 0.2): minimum-norm dx_i = lambda w_i n,
  // with lambda = (d - D) / sum(w^2).
  Stencil s;
  s.count = 3;
  s.vertex = {{0, 1, 2}};
  s.weight = {{0.5, 0.3, 0.2}};
  s.normal = V3(1, 0, 0);
  s.D = 0;
  const double d = 0.002, lambda = d / (0.25 + 0.09 + 0.04);
  const ZoneSolution sol = solveImpactZone({s}, {0}, d);
  EXPECT_NEAR(sol.lambda[0], lambda, 1e-12);
  for (int i = 0; i < 3; ++i)
    EXPECT_NEAR((displacementOf(sol, i) - lambda * s.weight[i] * s.normal).norm(), 0, 1e-12);
  // The weighted point then clears the ridge by exactly d.
  EXPECT_NEAR(gradDot(s, sol), d, 1e-12);
}

TEST(ImpactZones, TwoStencilZoneOnOneVertex) {
  // Orthogonal normals: dx = b1 n1 + b2 n2. At 60 degrees: solve the 2x2 system by hand.
  {
    const std::vector<Stencil> st = {vertexStencil(0, V3(1, 0, 0), -0.01), vertexStencil(0, V3(0, 1, 0), -0.02)};
    const ZoneSolution sol = solveImpactZone(st, {0, 1}, 0.0);
    EXPECT_NEAR((displacementOf(sol, 0) - V3(0.01, 0.02, 0)).norm(), 0, 1e-12);
  }
  {
    const V3 n1(1, 0, 0), n2(0.5, std::sqrt(3.0) / 2, 0);
    const std::vector<Stencil> st = {vertexStencil(0, n1, -0.01), vertexStencil(0, n2, -0.01)};
    const ZoneSolution sol = solveImpactZone(st, {0, 1}, 0.0);
    // n1.dx = 0.01 and n2.dx = 0.01 -> dx = (0.01, (0.01 - 0.005) / (sqrt(3)/2), 0)
    EXPECT_NEAR((displacementOf(sol, 0) - V3(0.01, 0.005 / (std::sqrt(3.0) / 2), 0)).norm(), 0, 1e-12);
    EXPECT_GT(sol.lambda[0], 0);
    EXPECT_GT(sol.lambda[1], 0);
  }
}

TEST(ImpactZones, LambdaStaysNonNegative) {
  // n1 alone already clears stencil 2 (n2 . (1 m n1) = 0.8 > 0.1): eq. 7 as an equality would pull
  // back along n2 (lambda2 < 0); with lambda >= 0 the answer is dx = n1 * 1 m and lambda2 = 0.
  const std::vector<Stencil> st = {vertexStencil(0, V3(0, 1, 0), -1.0), vertexStencil(0, V3(0.6, 0.8, 0), -0.1)};
  const ZoneSolution sol = solveImpactZone(st, {0, 1}, 0.0);
  EXPECT_NEAR(sol.lambda[1], 0.0, 1e-15);
  EXPECT_NEAR((displacementOf(sol, 0) - V3(0, 1, 0)).norm(), 0, 1e-12);
  for (double l : sol.lambda) EXPECT_GE(l, 0.0);
}

TEST(ImpactZones, DuplicateAndNearlyParallelStencilsStayFinite) {
  const std::vector<Stencil> dup = {vertexStencil(0, V3(0, 0, 1), -0.01), vertexStencil(0, V3(0, 0, 1), -0.01),
                                    vertexStencil(0, V3(0, 0, 1), -0.01)};
  const ZoneSolution a = solveImpactZone(dup, {0, 1, 2}, 0.001);
  EXPECT_NEAR((displacementOf(a, 0) - V3(0, 0, 0.011)).norm(), 0, 1e-9);
  EXPECT_TRUE(a.feasible);
  for (double eps : {1e-4, 1e-8, 1e-12}) {
    const std::vector<Stencil> par = {vertexStencil(0, V3(0, 0, 1), -0.01),
                                      vertexStencil(0, V3(eps, 0, 1), -0.01)};
    const ZoneSolution b = solveImpactZone(par, {0, 1}, 0.001);
    ASSERT_TRUE(displacementOf(b, 0).allFinite());
    EXPECT_LT(displacementOf(b, 0).norm(), 0.02) << eps;
    EXPECT_GE(gradDot(par[0], b), 0.011 - 1e-9);
    EXPECT_GE(gradDot(par[1], b), 0.011 - 1e-9);
  }
}

TEST(ImpactZones, OpposingStencilsAreReportedInfeasibleAndStayBounded) {
  // A vertex inside a thin slab: one face says up, the other says down (the paper's Fig. 5).
  const std::vector<Stencil> st = {vertexStencil(0, V3(0, 1, 0), -0.004), vertexStencil(0, V3(0, -1, 0), -0.006)};
  const ZoneSolution sol = solveImpactZone(st, {0, 1}, 0.001);
  EXPECT_FALSE(sol.feasible);
  EXPECT_GT(sol.max_violation, 0.001);
  ASSERT_TRUE(displacementOf(sol, 0).allFinite());
  EXPECT_LT(displacementOf(sol, 0).norm(), 0.01);
}

TEST(ImpactZones, ZonesGroupStencilsThatShareVertices) {
  Stencil f;
  f.count = 3;
  f.vertex = {{1, 2, 3}};
  f.weight = {{0.3, 0.3, 0.4}};
  const std::vector<Stencil> st = {vertexStencil(1, V3(0, 0, 1), -1), vertexStencil(7, V3(0, 0, 1), -1), f,
                                   vertexStencil(3, V3(0, 1, 0), -1), vertexStencil(9, V3(0, 1, 0), -1),
                                   vertexStencil(7, V3(1, 0, 0), -1)};
  const auto zones = groupImpactZones(st, 10);
  ASSERT_EQ(zones.size(), 3u);
  EXPECT_EQ(zones[0], (std::vector<int>{0, 2, 3}));
  EXPECT_EQ(zones[1], (std::vector<int>{1, 5}));
  EXPECT_EQ(zones[2], (std::vector<int>{4}));
}

TEST(ImpactZones, LargeZoneMeetsTheKktConditions) {
  // 150 stencils on 40 vertices (face stencils chain them into one zone): past the direct-solve
  // size, solved by Hildreth's method. Check feasibility, lambda >= 0 and complementarity.
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-1, 1), depth(-0.01, 0.0), w(0.1, 1.0);
  std::vector<Stencil> st;
  for (int i = 0; i < 150; ++i) {
    Stencil s;
    const V3 n = V3(u(rng), u(rng), 1.0 + std::abs(u(rng))).normalized();  // all roughly +z: feasible
    s.normal = n;
    s.D = depth(rng);
    if (i % 3 == 0) {
      s.count = 3;
      s.vertex = {{i % 40, (i + 1) % 40, (i + 2) % 40}};
      const double a = w(rng), b = w(rng), c = w(rng);
      s.weight = {{a / (a + b + c), b / (a + b + c), c / (a + b + c)}};
    } else {
      s = vertexStencil(i % 40, n, s.D);
    }
    st.push_back(s);
  }
  std::vector<int> zone(st.size());
  for (std::size_t i = 0; i < zone.size(); ++i) zone[i] = static_cast<int>(i);
  ASSERT_EQ(groupImpactZones(st, 40).size(), 1u);
  const double d = 0.001;
  const ZoneSolution sol = solveImpactZone(st, zone, d);
  EXPECT_TRUE(sol.feasible);
  EXPECT_GT(sol.sweeps, 0);
  for (std::size_t i = 0; i < st.size(); ++i) {
    const double slack = st[i].D + gradDot(st[i], sol) - d;
    EXPECT_GE(sol.lambda[i], 0);
    EXPECT_GE(slack, -1e-3 * d) << i;
    if (sol.lambda[i] > 1e-6) {
      EXPECT_LT(slack, 1e-3 * d) << "inactive stencil " << i << " has lambda " << sol.lambda[i];
    }
  }
}
