// Resolver options used by the evaluation: the per-iteration trace and its observer, the
// per-stencil baseline solver, the time budget and the best state, the inside-out body; and the
// zone conditioning report.
#include "test_helpers.h"
#include "virtual_tryon/core/resolve/impact_zones.h"
#include "virtual_tryon/core/resolve/penetration_resolver.h"
#include "virtual_tryon/core/scenes/procedural.h"
#include "virtual_tryon/testing/reference_bvh.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <limits>
#include <cmath>
#include <thread>

using namespace virtual_tryon;
using V3 = Eigen::Vector3d;
using virtual_tryon_test::vertexStencil;

namespace {

double secondsSince(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

}  // namespace

TEST(ResolverOptions, TraceFollowsTheRunAndObserverTimeIsLeftOut) {
  ResolveScene s = makeWrinkledTubeScene(48, 30);
  Body b(s.body);
  b.bvh();
  ReferenceReferee ref(s.body);
  ResolverParams p;
  p.objective = ResolverObjective::Paper;  // the rounds themselves
  int calls = 0;
  std::vector<std::size_t> independent;
  p.on_iteration = [&](const ResolverIteration&, const TriMesh& g) {
    ++calls;
    const ReferenceCounts c = ref.count(g);
    independent.push_back(c.garment_edge_crossings + c.body_edge_crossings);
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  };
  const auto t0 = std::chrono::steady_clock::now();
  const ResolverReport rep = resolvePenetrations(b, s.garment, p);
  const double wall = secondsSince(t0);
  ASSERT_TRUE(rep.converged) << rep.reason;
  ASSERT_GE(rep.trace.size(), 2u);
  EXPECT_EQ(calls, static_cast<int>(rep.trace.size()));
  EXPECT_EQ(rep.trace.front().iteration, 0);
  EXPECT_EQ(rep.trace.front().garment_edge_crossings, rep.garment_edge_crossings_before);
  EXPECT_EQ(rep.trace.front().body_edge_crossings, rep.body_edge_crossings_before);
  EXPECT_EQ(rep.trace.back().iteration, rep.iterations);
  EXPECT_EQ(rep.trace.back().garment_edge_crossings + rep.trace.back().body_edge_crossings, 0u);
  for (std::size_t i = 1; i < rep.trace.size(); ++i) {
    EXPECT_GE(rep.trace[i].seconds, rep.trace[i - 1].seconds);
    EXPECT_GT(rep.trace[i].stencils, 0u);
    EXPECT_GT(rep.trace[i].impact_zones, 0u);
  }
  EXPECT_GT(independent.front(), 100u);
  EXPECT_EQ(independent.back(), 0u);
  // The observer slept 20 ms per call; none of it is in the resolver's times.
  EXPECT_LE(rep.seconds_total, wall - 0.02 * calls + 1e-3);
  EXPECT_LE(rep.trace.back().seconds, rep.seconds_total);
}

TEST(ResolverOptions, PerStencilProjectionIsTheBaselineWithoutZones) {
  // One vertex behind two faces at right angles: the zone solve meets both constraints at once;
  // the independent projections, averaged, meet neither.
  const std::vector<Stencil> st = {vertexStencil(0, V3(1, 0, 0), -0.01), vertexStencil(0, V3(0, 1, 0), -0.01)};
  const ZoneSolution zone = solveImpactZone(st, {0, 1}, 0.001);
  EXPECT_TRUE(zone.feasible);
  EXPECT_NEAR((zone.displacement[0] - V3(0.011, 0.011, 0)).norm(), 0, 1e-12);
  const ZoneSolution jac = projectStencilsIndependently(st, 0.001);
  ASSERT_EQ(jac.vertices, std::vector<int>{0});
  EXPECT_NEAR((jac.displacement[0] - V3(0.0055, 0.0055, 0)).norm(), 0, 1e-12);
  EXPECT_FALSE(jac.feasible);
  EXPECT_NEAR(jac.max_violation, 0.0055, 1e-12);

  ResolveScene s = makeWrinkledTubeScene(48, 30);
  Body b(s.body);
  ResolverParams p;
  p.solver = ZoneSolver::PerStencilProjection;
  const ResolverReport rep = resolvePenetrations(b, s.garment, p);
  EXPECT_EQ(rep.impact_zones, 0u);
  EXPECT_GE(rep.iterations, 1);
  for (const auto& it : rep.trace) EXPECT_EQ(it.impact_zones, 0u);
  // Whatever it reaches, the report describes the garment it leaves.
  TriMesh again = s.garment;
  ResolverParams count;
  count.max_iterations = 0;
  const ResolverReport recount = resolvePenetrations(b, again, count);
  EXPECT_EQ(recount.garment_edge_crossings_before, rep.garment_edge_crossings_after);
  EXPECT_EQ(recount.body_edge_crossings_before, rep.body_edge_crossings_after);
}

TEST(ResolverOptions, TimeBudgetStopsWithTheBestStateAndSaysSo) {
  ResolveScene s = makeWrinkledTubeScene(48, 30);
  const TriMesh start = s.garment;
  Body b(s.body);
  ResolverParams p;
  p.objective = ResolverObjective::Paper;  // the rounds themselves
  p.time_budget = 1e-9;  // spent by the first detection
  const ResolverReport rep = resolvePenetrations(b, s.garment, p);
  EXPECT_FALSE(rep.converged);
  EXPECT_TRUE(rep.time_budget_spent);
  EXPECT_NE(rep.reason.find("time budget"), std::string::npos) << rep.reason;
  EXPECT_EQ(rep.iterations, 0);
  EXPECT_EQ((s.garment.V - start.V).norm(), 0.0);
  EXPECT_EQ(rep.garment_edge_crossings_after, rep.garment_edge_crossings_before);

  // A budget spent half-way: the observer burns it after the first round. The budget is three
  // times what an unobserved run takes on this build (sanitizers make it several times slower).
  TriMesh unobserved = start;
  ResolverParams paper;
  paper.objective = ResolverObjective::Paper;
  const ResolverReport plain = resolvePenetrations(b, unobserved, paper);
  ASSERT_TRUE(plain.converged) << plain.reason;
  const double budget = 3.0 * plain.seconds_total + 0.01;
  TriMesh g = start;
  ResolverParams q;
  q.objective = ResolverObjective::Paper;  // the rounds themselves
  q.time_budget = budget;
  q.on_iteration = [budget](const ResolverIteration& it, const TriMesh&) {
    if (it.iteration == 1) {
      const auto t0 = std::chrono::steady_clock::now();
      while (secondsSince(t0) < 1.2 * budget) {
      }
    }
  };
  // Observer time does not count against the budget either: this run converges.
  const ResolverReport full = resolvePenetrations(b, g, q);
  EXPECT_TRUE(full.converged) << full.reason;
  EXPECT_FALSE(full.time_budget_spent);
}

TEST(ResolverOptions, AStopWithoutConvergingReturnsTheStateWithTheSmallestError) {
  // The error is crossings plus vertices inside; the trace's inside counts (tracked per moved
  // vertex) must agree with a full classification of the state returned.
  // 41 segments: the tube's vertices do not line up with the capsule's 48 seams (where a crossing
  // through a shared body edge may count once or twice, and parity says nothing).
  ResolveScene s = makeWrinkledTubeScene(41, 29);
  Body b(s.body);
  int stopped = 0;
  for (int limit : {1, 2, 3}) {
    TriMesh g = s.garment;
    ResolverParams p;
    p.objective = ResolverObjective::Paper;  // the rounds themselves
    p.max_iterations = limit;
    p.solver = ZoneSolver::PerStencilProjection;
    const ResolverReport rep = resolvePenetrations(b, g, p);
    if (rep.converged) continue;
    ++stopped;
    std::size_t fewest = static_cast<std::size_t>(-1);
    for (const auto& it : rep.trace)
      fewest = std::min(fewest, it.garment_edge_crossings + it.body_edge_crossings + it.vertices_inside);
    EXPECT_EQ(rep.garment_edge_crossings_after + rep.body_edge_crossings_after + rep.vertices_inside_after, fewest);
    TriMesh again = g;
    ResolverParams count;
    count.max_iterations = 0;
    const ResolverReport recount = resolvePenetrations(b, again, count);
    EXPECT_EQ(recount.garment_edge_crossings_before + recount.body_edge_crossings_before +
                  recount.vertices_inside_before,
              fewest);
    // The independent referee sees the same vertices inside.
    EXPECT_EQ(ReferenceReferee(s.body).count(g).vertices_inside, recount.vertices_inside_before);
  }
  EXPECT_GT(stopped, 0);
}

TEST(ResolverOptions, TracedInsideCountsAgreeWithTheReferee) {
  // 41 segments: the tube's vertices do not line up with the capsule's 48 seams (where a crossing
  // through a shared body edge may count once or twice, and parity says nothing).
  ResolveScene s = makeWrinkledTubeScene(41, 29);
  Body b(s.body);
  ReferenceReferee ref(s.body);
  ResolverParams p;
  int checked = 0;
  p.on_iteration = [&](const ResolverIteration& it, const TriMesh& g) {
    EXPECT_EQ(it.vertices_inside, ref.count(g).vertices_inside) << "iteration " << it.iteration;
    ++checked;
  };
  EXPECT_TRUE(resolvePenetrations(b, s.garment, p).converged);
  EXPECT_GE(checked, 3);
}

TEST(ResolverOptions, ADeepRegionKeepsProgressingWhileItsCrossingsStayLevel) {
  // A strip 0.1 m deep in a capsule: each round clears a row from the rim, the number of
  // crossings stays about the same, the vertices inside fall. No stall.
  const TriMesh torso = makeCapsule(0.15, 0.6, V3::Zero(), 48, 24);
  TriMesh patch = transformed(makePatch(0.4, 0.2, 40, 20), V3::UnitX(), M_PI / 2, V3(0, 0, 0.05));
  Body b(torso);
  ResolverParams paper;  // the rounds themselves (smooth pushes the strip out before them)
  paper.objective = ResolverObjective::Paper;
  const ResolverReport rep = resolvePenetrations(b, patch, paper);
  EXPECT_EQ(rep.reason.find("no progress for"), std::string::npos) << rep.reason;
  EXPECT_GT(rep.iterations, 12);
}

TEST(ResolverOptions, AnInsideOutBodyIsRefusedAndNothingMoves) {
  TriMesh sphere = makeSphere(0.1, V3::Zero(), 3);
  for (Eigen::Index f = 0; f < sphere.F.rows(); ++f) std::swap(sphere.F(f, 1), sphere.F(f, 2));
  TriMesh garment = makePatch(0.12, 0.12, 12, 12, V3(0, 0.08, 0));
  const TriMesh start = garment;
  Body b(sphere);
  ASSERT_TRUE(b.closed());
  ASSERT_LT(b.signedVolume(), 0);
  const ResolverReport rep = resolvePenetrations(b, garment);
  EXPECT_FALSE(rep.converged);
  EXPECT_NE(rep.reason.find("inside out"), std::string::npos) << rep.reason;
  EXPECT_EQ((garment.V - start.V).norm(), 0.0);
}

TEST(ResolverOptions, PushOutOfAPieceWhollyInsideIsTracedAndCountedOnce) {
  const TriMesh arm = makeCylinder(0.05, 0.4, V3::Zero(), 40, 10, true);
  TriMesh sleeve = makeCylinder(0.04, 0.2, V3::Zero(), 30, 12, false);
  // A second piece, outside and untouched.
  sleeve = concatenate(sleeve, makePatch(0.05, 0.05, 5, 5, V3(0, 0.5, 0)));
  Body b(arm);
  const ResolverReport rep = resolvePenetrations(b, sleeve);
  EXPECT_TRUE(rep.converged) << rep.reason;
  EXPECT_EQ(rep.vertices_inside_before, 30u * 13u);
  EXPECT_EQ(rep.vertices_inside_after, 0u);
  bool pushed = false;
  for (const auto& it : rep.trace) pushed = pushed || it.push_out;
  EXPECT_TRUE(pushed);
  EXPECT_EQ(ReferenceReferee(arm).count(sleeve).vertices_inside, 0u);
}

TEST(ZoneConditioning, EigenvaluesOfDuplicateParallelAndOrthogonalStencils) {
  const std::vector<Stencil> ortho = {vertexStencil(0, V3(1, 0, 0), -0.01), vertexStencil(0, V3(0, 1, 0), -0.01)};
  const ZoneConditioning a = zoneConditioning(ortho, {0, 1});
  ASSERT_TRUE(a.computed);
  EXPECT_NEAR(a.condition, 1.0, 1e-12);
  const std::vector<Stencil> dup = {vertexStencil(0, V3(0, 0, 1), -0.01), vertexStencil(0, V3(0, 0, 1), -0.01)};
  const ZoneConditioning b = zoneConditioning(dup, {0, 1});
  EXPECT_TRUE(std::isinf(b.condition));
  EXPECT_NEAR(b.regularized_condition, 2.0 / 1e-10, 1e2);
  const double th = 1e-3;
  const std::vector<Stencil> par = {vertexStencil(0, V3(0, 0, 1), -0.01),
                                    vertexStencil(0, V3(std::sin(th), 0, std::cos(th)), -0.01)};
  const ZoneConditioning c = zoneConditioning(par, {0, 1});
  const double cs = std::cos(th);
  EXPECT_NEAR(c.condition, (1 + cs) / (1 - cs), 1e-3 * (1 + cs) / (1 - cs));
  EXPECT_FALSE(zoneConditioning(dup, {0, 1}, 1).computed);
}

// The garment's least distance to the body's surface, by the referee's own tree.
double leastDistance(const TriMesh& body, const TriMesh& garment) {
  const ReferenceTree tree(body);
  double least = std::numeric_limits<double>::infinity();
  for (Eigen::Index v = 0; v < garment.V.rows(); ++v)
    least = std::min(least, tree.distance(body, garment.V.row(v).transpose()));
  return least;
}

TEST(ResolverOptions, BodyUncertaintyKeepsTheGarmentThatMuchFartherOut) {
  // A patch 1 mm above a sphere's top: no crossing, so without uncertainty nothing moves; with a
  // 3 mm uncertainty every vertex ends at least d + 3 mm from the surface, and still clean.
  const TriMesh sphere = makeSphere(0.1, V3::Zero(), 4);
  Body b(sphere);
  const TriMesh start = makePatch(0.12, 0.12, 24, 24, V3(0, 0.101, 0));
  ASSERT_GT(leastDistance(sphere, start), 0.0009);
  ASSERT_LT(leastDistance(sphere, start), 0.0011);

  TriMesh plain = start;
  const ResolverReport p = resolvePenetrations(b, plain);
  EXPECT_TRUE(p.converged) << p.reason;
  EXPECT_EQ(p.moved_vertices, 0u);
  EXPECT_EQ(p.near_vertices_pushed, 0u);
  EXPECT_EQ((plain.V - start.V).norm(), 0.0);

  for (double u : {0.001, 0.003}) {
    ResolverParams params;
    params.body_uncertainty = u;
    TriMesh garment = start;
    const ResolverReport r = resolvePenetrations(b, garment, params);
    EXPECT_TRUE(r.converged) << r.reason;
    EXPECT_DOUBLE_EQ(r.body_uncertainty, u);
    EXPECT_NEAR(r.clearance, p.clearance + u, 1e-12);
    EXPECT_GT(r.near_vertices_pushed, 0u);
    const double least = leastDistance(sphere, garment);
    EXPECT_GE(least, r.clearance - 1e-9) << "u " << u;
    EXPECT_LT(least, r.clearance + 0.001) << "moved farther than asked, u " << u;  // no needless lift
    const ReferenceCounts c = ReferenceReferee(sphere).count(garment);
    EXPECT_EQ(c.garment_edge_crossings + c.body_edge_crossings + c.vertices_inside, 0u);
    EXPECT_LT(r.max_edge_strain, 0.1) << "u " << u;
  }
}

TEST(ResolverOptions, BodyUncertaintyClearsAPenetratingGarmentByTheWholeClearance) {
  const ResolveScene s = makeWrinkledTubeScene(48, 30);
  Body b(s.body);
  ResolverParams params;
  params.body_uncertainty = 0.002;
  TriMesh garment = s.garment;
  const ResolverReport r = resolvePenetrations(b, garment, params);
  EXPECT_TRUE(r.converged) << r.reason;
  const ReferenceCounts c = ReferenceReferee(s.body).count(garment);
  EXPECT_EQ(c.garment_edge_crossings, 0u);
  EXPECT_EQ(c.body_edge_crossings, 0u);
  EXPECT_EQ(c.vertices_inside, 0u);
  EXPECT_GE(leastDistance(s.body, garment), r.clearance - 1e-9);
}

namespace {

// The least distance from the points of `garment`'s faces (a 12 x 12 barycentric grid on each,
// corners included) to the analytic sphere of radius r about the origin.
double leastFaceDistanceToSphere(const TriMesh& garment, double r) {
  double least = 1e30;
  const int n = 12;
  for (Eigen::Index f = 0; f < garment.F.rows(); ++f)
    for (int i = 0; i <= n; ++i)
      for (int j = 0; i + j <= n; ++j) {
        const double a = double(i) / n, b = double(j) / n;
        const V3 p = (1 - a - b) * garment.V.row(garment.F(f, 0)).transpose() +
                     a * garment.V.row(garment.F(f, 1)).transpose() + b * garment.V.row(garment.F(f, 2)).transpose();
        least = std::min(least, p.norm() - r);
      }
  return least;
}

}  // namespace

TEST(ResolverOptions, BodyUncertaintyKeepsTheMiddleOfALargeFaceOutToo) {
  // One 6 cm quad (two triangles) over the top of a 10 cm sphere: its middle 2 mm above the top,
  // its corners 10.5 mm out. With d = 1 mm and u = 3 mm no corner is nearer than d + u, and still
  // the face's middle, over the bulge, must clear the sphere by 4 mm (a garment face wider than
  // the body's faces). Judged against the analytic sphere, which the mesh's vertices lie on.
  const double r = 0.1;
  const TriMesh sphere = makeSphere(r, V3::Zero(), 4);
  Body b(sphere);
  TriMesh quad;
  quad.V.resize(4, 3);
  quad.V << -0.03, 0.102, -0.03, 0.03, 0.102, 0.03, 0.03, 0.102, -0.03, -0.03, 0.102, 0.03;
  quad.F.resize(2, 3);
  quad.F << 0, 3, 1, 0, 1, 2;
  ASSERT_LT(leastFaceDistanceToSphere(quad, r), 0.0021);
  ASSERT_GT(leastDistance(sphere, quad), 0.01);

  ResolverParams params;
  params.clearance = 0.001;
  params.body_uncertainty = 0.003;
  TriMesh garment = quad;
  const ResolverReport rep = resolvePenetrations(b, garment, params);
  ASSERT_TRUE(rep.converged) << rep.reason;
  EXPECT_EQ(rep.near_vertices_pushed, 4u);  // lifted with their face
  // The sphere bulges above its mesh's faces by at most about 0.15 mm between vertices.
  const double least = leastFaceDistanceToSphere(garment, r);
  EXPECT_GE(least, 0.004 - 0.0003);
  EXPECT_LT(least, 0.004 + 0.001) << "lifted farther than asked";

  // Without the face clearance nothing is near enough to move.
  params.relaxation.face_clearance = -1;
  TriMesh cornersOnly = quad;
  const ResolverReport off = resolvePenetrations(b, cornersOnly, params);
  ASSERT_TRUE(off.converged);
  EXPECT_EQ(off.moved_vertices, 0u);
  EXPECT_LT(leastFaceDistanceToSphere(cornersOnly, r), 0.0021);
}
