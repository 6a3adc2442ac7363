// The resolver on procedural scenes; every "zero crossings" is checked by the independent
// brute-force referee (reference_check.h), not by the resolver's own detector.
#include "virtual_tryon/core/resolve/intersections.h"
#include "virtual_tryon/core/resolve/penetration_resolver.h"
#include "virtual_tryon/core/scenes/procedural.h"
#include "virtual_tryon/testing/reference_check.h"
#include "virtual_tryon/core/resolve/stencils.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>

using namespace virtual_tryon;
using V3 = Eigen::Vector3d;

namespace {

void expectClean(const TriMesh& body, const TriMesh& garment) {
  const ReferenceCounts c = referenceCounts(body, garment);
  EXPECT_EQ(c.garment_edge_crossings, 0u);
  EXPECT_EQ(c.body_edge_crossings, 0u);
  EXPECT_EQ(c.vertices_inside, 0u);
}

}  // namespace

TEST(Stencils, IllegalVertexIsTheEndPointBehindTheFace) {
  // A body of one upward face; a garment triangle with one vertex below it.
  TriMesh body;
  body.V.resize(3, 3);
  body.V << -1, 0, -1, 1, 0, -1, 0, 0, 2;  // normal: (2,0,0) x (1,0,3) -> (0,-6,0)? wind it upward:
  body.F.resize(1, 3);
  body.F << 0, 2, 1;  // (0,0,3)x(2,0,0)... normal +y
  Body b(body);
  ASSERT_GT(b.faceNormals()(0, 1), 0.99);
  TriMesh g;
  g.V.resize(3, 3);
  g.V << 0, -0.01, 0, 0.1, 0.05, 0.1, -0.1, 0.05, 0.1;
  g.F.resize(1, 3);
  g.F << 0, 1, 2;
  GarmentTopology topo(g);
  CrossingSet cs;
  detectCrossings(b, g, topo, cs);
  ASSERT_EQ(cs.garment_edges.size(), 2u);  // the two edges leaving vertex 0
  std::vector<int> illegal;
  const auto st = buildStencils(b, g, topo, cs, &illegal);
  EXPECT_EQ(illegal, std::vector<int>{0});
  ASSERT_EQ(st.size(), 1u);  // both edges cross the same face: one stencil
  EXPECT_NEAR(st[0].D, -0.01, 1e-15);
  // Resolving moves only vertex 0, straight up to the clearance.
  TriMesh moved = g;
  ResolverParams p;
  p.objective = ResolverObjective::Paper;  // the rounds alone (smooth: resolver_shape_test.cpp)
  p.clearance = 0.002;
  const ResolverReport rep = resolvePenetrations(b, moved, p);
  EXPECT_TRUE(rep.converged) << rep.reason;
  EXPECT_EQ(rep.iterations, 1);
  EXPECT_NEAR((moved.V.row(0) - Eigen::RowVector3d(0, 0.002, 0)).norm(), 0, 1e-12);
  EXPECT_EQ((moved.V.bottomRows(2) - g.V.bottomRows(2)).norm(), 0.0);
}

TEST(Detection, SharedOutAmongThreadsFindsWhatOneThreadFinds) {
  // 4,608 garment faces: the whole detection is shared out among threads (on a machine with more
  // than one); chunks of 200 faces are each detected by one thread. Same crossings, same order.
  ResolveScene s = makeWrinkledTubeScene(48, 48);
  ASSERT_GT(s.garment.F.rows(), 2000);
  Body b(s.body);
  const GarmentTopology topo(s.garment);
  CrossingSet all;
  detectCrossings(b, s.garment, topo, all);
  ASSERT_GT(all.size(), 100u);
  CrossingSet joined;
  for (int first = 0; first < s.garment.F.rows(); first += 200) {
    std::vector<int> chunk;
    for (int f = first; f < std::min<int>(first + 200, static_cast<int>(s.garment.F.rows())); ++f) chunk.push_back(f);
    CrossingSet part;
    detectCrossings(b, s.garment, topo, part, &chunk);
    joined.garment_edges.insert(joined.garment_edges.end(), part.garment_edges.begin(), part.garment_edges.end());
    joined.body_edges.insert(joined.body_edges.end(), part.body_edges.begin(), part.body_edges.end());
  }
  auto key = [](const std::vector<EdgeFaceCrossing>& v) {
    std::vector<std::array<double, 4>> k;
    for (const auto& c : v) k.push_back({double(c.edge), double(c.face), c.t, c.s0});
    std::sort(k.begin(), k.end());
    k.erase(std::unique(k.begin(), k.end()), k.end());
    return k;
  };
  EXPECT_EQ(key(all.garment_edges), key(joined.garment_edges));
  EXPECT_EQ(key(all.body_edges), key(joined.body_edges));
  EXPECT_EQ(key(all.garment_edges).size(), all.garment_edges.size());  // already sorted and unique
}

TEST(Detection, KeptCandidatesFindWhatTheTreeFindsWhileTheGarmentMoves) {
  // The wrinkled tube moved in steps: small ones (inside the kept boxes: the candidates are
  // reused) and one larger than the margin (the boxes are left: the tree is asked again). After
  // every step the detection with kept candidates equals the plain one, crossing for crossing.
  ResolveScene s = makeWrinkledTubeScene(24, 24);
  Body b(s.body);
  const GarmentTopology topo(s.garment);
  CandidateCache cache(0.002);
  std::vector<int> faces;
  for (int f = 0; f < s.garment.F.rows(); f += 2) faces.push_back(f);  // half the faces, distinct
  auto same = [](const std::vector<EdgeFaceCrossing>& a, const std::vector<EdgeFaceCrossing>& c) {
    if (a.size() != c.size()) return false;
    for (std::size_t i = 0; i < a.size(); ++i)
      if (a[i].edge != c[i].edge || a[i].face != c[i].face || a[i].t != c[i].t || a[i].bary != c[i].bary) return false;
    return true;
  };
  const double steps[] = {0, 0.0003, -0.0006, 0.0009, 0.004, 0.0002, -0.0045};
  std::size_t queriedBefore = 0;
  for (double step : steps) {
    // A radial move of every vertex (the tube's axis is y), growing and shrinking the tube.
    for (Eigen::Index v = 0; v < s.garment.V.rows(); ++v) {
      Eigen::RowVector3d r = s.garment.V.row(v);
      r.y() = 0;
      if (r.norm() > 0) s.garment.V.row(v) += step * r.normalized();
    }
    CrossingSet plain, kept;
    detectCrossings(b, s.garment, topo, plain, &faces);
    detectCrossings(b, s.garment, topo, kept, &faces, cache);
    EXPECT_GT(plain.size(), 0u);
    EXPECT_TRUE(same(plain.garment_edges, kept.garment_edges)) << "step " << step;
    EXPECT_TRUE(same(plain.body_edges, kept.body_edges)) << "step " << step;
    if (std::abs(step) >= 0.004) EXPECT_GT(cache.queried, queriedBefore);  // left its boxes: asked again
    queriedBefore = cache.queried;
  }
  EXPECT_GT(cache.reused, cache.queried);  // most steps stayed inside the kept boxes
  EXPECT_EQ(cache.reused + cache.queried, faces.size() * (sizeof steps / sizeof steps[0]));
}

TEST(Resolver, SphereWithPatchThroughItsCap) {
  // A cloth patch 2 cm below the top of a 10 cm sphere: its middle is inside.
  const TriMesh body = makeSphere(0.1, V3::Zero(), 4);
  TriMesh garment = makePatch(0.12, 0.12, 24, 24, V3(0.003, 0.08, -0.002));
  const ReferenceCounts before = referenceCounts(body, garment);
  ASSERT_GT(before.vertices_inside, 20u);
  ASSERT_GT(before.garment_edge_crossings, 20u);
  Body b(body);
  ResolverParams paper;  // the rounds find the illegal vertices (smooth pushes them out first)
  paper.objective = ResolverObjective::Paper;
  const ResolverReport rep = resolvePenetrations(b, garment, paper);
  EXPECT_TRUE(rep.converged) << rep.reason;
  EXPECT_EQ(rep.garment_edge_crossings_after + rep.body_edge_crossings_after, 0u);
  EXPECT_GT(rep.illegal_vertices, 0u);
  EXPECT_GT(rep.max_displacement, 0.005);
  EXPECT_LT(rep.max_displacement, 0.05);
  EXPECT_EQ(rep.vertices_inside_before, before.vertices_inside);
  expectClean(body, garment);
}

TEST(Resolver, WrinkledTubeAroundACapsule) {
  ResolveScene s = makeWrinkledTubeScene(48, 30);
  const ReferenceCounts before = referenceCounts(s.body, s.garment);
  ASSERT_GT(before.garment_edge_crossings, 100u);
  ASSERT_GT(before.body_edge_crossings, 10u);
  Body b(s.body);
  const ResolverReport rep = resolvePenetrations(b, s.garment);
  EXPECT_TRUE(rep.converged) << rep.reason;
  EXPECT_LE(rep.iterations, 20);
  // The tube's vertices line up with the capsule's seams (48 segments each), so many crossings
  // pass exactly through shared body edges: counts may differ by how such a crossing is counted,
  // but both detectors see the penetration, and the referee finds none after.
  EXPECT_GT(rep.garment_edge_crossings_before, 100u);
  // The deepest wrinkle dips 1.5 cm in: nothing should need to move much more than that.
  EXPECT_GT(rep.max_displacement, 0.01);
  EXPECT_LT(rep.max_displacement, 0.03);
  expectClean(s.body, s.garment);
}

TEST(Resolver, TubeAroundACylinderShrunkInside) {
  // A sleeve 1 cm narrower than a 5 cm cylinder "arm", shorter than the arm: wholly inside but
  // for its edges' crossings at no point... it has none: every vertex is inside, no edge crosses.
  const TriMesh arm = makeCylinder(0.05, 0.4, V3::Zero(), 40, 10, true);
  TriMesh sleeve = makeCylinder(0.04, 0.2, V3::Zero(), 30, 12, false);
  Body b(arm);
  ResolverParams p;
  p.push_out_inside = false;
  TriMesh reported = sleeve;
  const ResolverReport r1 = resolvePenetrations(b, reported, p);
  EXPECT_FALSE(r1.converged);
  EXPECT_EQ(r1.garment_edge_crossings_before, 0u);
  EXPECT_EQ(r1.vertices_inside_before, static_cast<std::size_t>(sleeve.V.rows()));
  EXPECT_EQ(r1.vertices_inside_after, static_cast<std::size_t>(sleeve.V.rows()));
  EXPECT_NE(r1.reason.find("wholly inside"), std::string::npos) << r1.reason;
  EXPECT_EQ((reported.V - sleeve.V).norm(), 0.0);
  // Pushed out (the default): converged and clean.
  const ResolverReport r2 = resolvePenetrations(b, sleeve);
  EXPECT_TRUE(r2.converged) << r2.reason;
  EXPECT_EQ(r2.vertices_inside_after, 0u);
  expectClean(arm, sleeve);
}

TEST(Resolver, GarmentWithoutPenetrationCostsOneDetectionAndMovesNothing) {
  const TriMesh body = makeSphere(0.1, V3::Zero(), 3);
  TriMesh garment = makePatch(0.1, 0.1, 10, 10, V3(0, 0.2, 0));
  const TriMesh before = garment;
  Body b(body);
  const ResolverReport rep = resolvePenetrations(b, garment);
  EXPECT_TRUE(rep.converged);
  EXPECT_EQ(rep.iterations, 0);
  EXPECT_EQ(rep.moved_vertices, 0u);
  EXPECT_EQ(rep.impact_zones, 0u);
  EXPECT_EQ((garment.V - before.V).norm(), 0.0);
}

TEST(Resolver, FingerThroughACoarseGarmentIsReportedNotConverged) {
  // The paper's Fig. 5 kind: a thin closed "finger" pierces one triangle of a coarse garment. The
  // body's normals round the finger point every way; no displacement of that triangle along them
  // clears it, and the resolver must say so within its limits instead of looping.
  const TriMesh finger = makeCylinder(0.01, 0.2, V3::Zero(), 16, 3, true);
  TriMesh garment = makePatch(0.3, 0.3, 2, 2, V3(0.031, 0.0, -0.047));
  const ReferenceCounts before = referenceCounts(finger, garment);
  ASSERT_EQ(before.garment_edge_crossings, 0u);
  ASSERT_GT(before.body_edge_crossings, 0u);
  Body b(finger);
  ResolverParams p;
  p.max_iterations = 60;
  const ResolverReport rep = resolvePenetrations(b, garment, p);
  EXPECT_FALSE(rep.converged);
  EXPECT_LE(rep.iterations, 60);
  EXPECT_GT(rep.infeasible_zones, 0u);
  EXPECT_GT(rep.body_edge_crossings_after, 0u);
  EXPECT_NE(rep.reason.find("Fig. 5"), std::string::npos) << rep.reason;
  EXPECT_TRUE(garment.V.allFinite());
  // Contradicting zones are left where they are, not pushed some arbitrary way.
  EXPECT_EQ(rep.max_displacement, 0.0);
}

TEST(Resolver, OpenBodySkipsTheInsideTestAndStillResolvesCrossings) {
  TriMesh tube = makeCylinder(0.1, 0.4, V3::Zero(), 32, 8, false);  // open: no inside
  TriMesh patch = makePatch(0.1, 0.1, 10, 10, V3(0.1, 0.0, 0.0));  // horizontal, through the wall
  Body b(tube);
  ASSERT_FALSE(b.closed());
  ASSERT_GT(referenceCounts(tube, patch, false).garment_edge_crossings, 0u);
  const ResolverReport rep = resolvePenetrations(b, patch);
  EXPECT_TRUE(rep.converged) << rep.reason;
  EXPECT_FALSE(rep.body_closed);
  const ReferenceCounts after = referenceCounts(tube, patch, false);
  EXPECT_EQ(after.garment_edge_crossings + after.body_edge_crossings, 0u);
}
