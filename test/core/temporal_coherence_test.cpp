// limitCorrectionChange (core/resolve/temporal_coherence.h) on the project's wrinkled tube scene moved
// a little every frame (rounded to float, as a point cache holds it: enough to change some of the
// resolver's decisions), every frame resolved on its own. Bringing each correction's change within
// the limit keeps every frame clean by the independent referee.
#include "virtual_tryon/core/body/body.h"
#include "virtual_tryon/core/geometry/point_queries.h"
#include "virtual_tryon/core/resolve/penetration_resolver.h"
#include "virtual_tryon/core/resolve/temporal_coherence.h"
#include "virtual_tryon/core/scenes/procedural.h"
#include "virtual_tryon/core/scenes/procedural_animation.h"
#include "virtual_tryon/testing/reference_check.h"

#include <Eigen/Geometry>
#include <gtest/gtest.h>

#include <memory>

using namespace virtual_tryon;

namespace {

double largestChange(const MatrixX3d& resolved, const MatrixX3d& input, const MatrixX3d& previous) {
  return ((resolved - input) - previous).rowwise().norm().maxCoeff();
}

}  // namespace

TEST(TemporalCoherence, CorrectionsChangeWithinTheLimitAndEveryFrameStaysClean) {
  const ResolveScene scene = makeWrinkledTubeScene();
  std::vector<MatrixX3d> bodyFrames, garmentFrames;
  for (int f = 0; f < 8; ++f) {
    const Eigen::RowVector3d shift(0.01 * f, 0.002 * f, -0.003 * f);
    bodyFrames.push_back((scene.body.V.rowwise() + shift).cast<float>().cast<double>());
    garmentFrames.push_back((scene.garment.V.rowwise() + shift).cast<float>().cast<double>());
  }
  CoherenceParams cp;
  cp.max_change = 0.001;
  std::unique_ptr<Body> body;
  MatrixX3d previous;
  double coldMax = 0, coherentMax = 0;
  std::size_t candidates = 0, held = 0;
  for (std::size_t f = 0; f < bodyFrames.size(); ++f) {
    body = body ? std::make_unique<Body>(std::move(*body), bodyFrames[f])
                : std::make_unique<Body>(TriMesh{bodyFrames[f], scene.body.F});
    const MatrixX3d& input = garmentFrames[f];
    TriMesh garment{input, scene.garment.F};
    const ResolverReport rep = resolvePenetrations(*body, garment, ResolverParams());
    ASSERT_TRUE(rep.converged) << f << ": " << rep.reason;
    if (previous.rows() == input.rows()) {
      coldMax = std::max(coldMax, largestChange(garment.V, input, previous));
      cp.min_clearance = 0.5 * rep.clearance;
      const CoherenceReport c = limitCorrectionChange(*body, garment, input, previous, cp);
      EXPECT_TRUE(c.message.empty()) << c.message;
      EXPECT_EQ(c.limited + c.partly + c.held, c.candidates);
      EXPECT_NEAR(c.change_after, largestChange(garment.V, input, previous), 1e-12);
      EXPECT_LE(c.change_after, c.change_before + 1e-12);
      candidates += c.candidates;
      held += c.held + c.partly;
      coherentMax = std::max(coherentMax, c.change_after);
    }
    const ReferenceCounts counts = referenceCounts(body->mesh(), garment, body->closed());
    EXPECT_EQ(counts.garment_edge_crossings + counts.body_edge_crossings + counts.vertices_inside, 0u) << f;
    previous = garment.V - input;
  }
  std::printf("largest change of a correction: %.2f mm cold, %.2f mm limited (%zu vertices over, %zu left over)\n",
              1e3 * coldMax, 1e3 * coherentMax, candidates, held);
  // The premise: resolved cold, some correction jumps by more than the limit.
  ASSERT_GT(coldMax, cp.max_change);
  ASSERT_GT(candidates, 0u);
  EXPECT_EQ(held, 0u);
  EXPECT_LE(coherentMax, cp.max_change * (1 + 1e-6));
  EXPECT_LT(coherentMax, coldMax);
}

TEST(TemporalCoherence, SizesThatDoNotMatchLeaveTheGarmentAlone) {
  const ProceduralAnimation anim = makeProceduralAnimation(ProceduralAnimationParams());
  const Body body(TriMesh{anim.body_frames[0], anim.body.F});
  TriMesh garment{anim.garment_frames[0], anim.garment.F};
  const MatrixX3d before = garment.V;
  const CoherenceReport c = limitCorrectionChange(body, garment, before, MatrixX3d::Zero(3, 3));
  EXPECT_FALSE(c.message.empty());
  EXPECT_EQ(garment.V, before);
}

// A vertex whose previous correction, on this frame's input, lies 1 cm inside the body cannot come
// within 3 mm of it and stay clean: it is left over and counted as forced by the input (the
// body's own queries confirm the point is inside and that deep). One whose previous correction lies
// 5 mm further out is brought to 3 mm from it, and is not counted.
TEST(TemporalCoherence, AChangeTheInputForcesIsCountedAsForced) {
  const ResolveScene scene = makeWrinkledTubeScene();
  const Body body(scene.body);
  const MatrixX3d input = scene.garment.V;
  TriMesh garment{input, scene.garment.F};
  ASSERT_TRUE(resolvePenetrations(body, garment, ResolverParams()).converged);
  const MatrixX3d correction = garment.V - input;
  MatrixX3d previous = correction;
  // The deep vertex: its nearest body point moved 1 cm into the body along that face's normal.
  const int deep = 0, outside = static_cast<int>(input.rows() / 2);
  const ClosestPoint cp = closestPointOnBody(body, garment.V.row(deep).transpose());
  const Eigen::Vector3d inside = cp.point - 0.01 * body.faceNormals().row(cp.face).transpose();
  ASSERT_TRUE(pointInsideBody(body, inside));
  ASSERT_GT(closestPointOnBody(body, inside).distance, 0.003);
  previous.row(deep) = inside.transpose() - input.row(deep);
  // The other: its previous correction 5 mm further out than now, along its body normal.
  const ClosestPoint co = closestPointOnBody(body, garment.V.row(outside).transpose());
  previous.row(outside) += 0.005 * body.faceNormals().row(co.face);
  CoherenceParams cp3;
  cp3.max_change = 0.003;
  const CoherenceReport c = limitCorrectionChange(body, garment, input, previous, cp3);
  ASSERT_TRUE(c.message.empty()) << c.message;
  EXPECT_EQ(c.candidates, 2u);
  EXPECT_EQ(c.forced_by_input, 1u);
  EXPECT_EQ(c.limited, 1u);  // the outer one, brought to 3 mm: over the limit only where forced
  EXPECT_GE(c.partly + c.held, c.forced_by_input);
  const Eigen::RowVector3d deepChange = (garment.V.row(deep) - input.row(deep)) - previous.row(deep);
  EXPECT_GT(deepChange.norm(), 0.003);
  EXPECT_NEAR(c.change_after, ((garment.V - input) - previous).rowwise().norm().maxCoeff(), 1e-12);
  // Without the deep vertex, the largest change is the unforced one.
  double unforced = 0;
  for (Eigen::Index v = 0; v < input.rows(); ++v)
    if (v != deep) unforced = std::max(unforced, ((garment.V.row(v) - input.row(v)) - previous.row(v)).norm());
  EXPECT_NEAR(c.change_after_unforced, unforced, 1e-12);
  EXPECT_LE(c.change_after_unforced, c.change_after);
  const ReferenceCounts counts = referenceCounts(body.mesh(), garment, body.closed());
  EXPECT_EQ(counts.garment_edge_crossings + counts.body_edge_crossings + counts.vertices_inside, 0u);
}

namespace {

// The wrinkled tube resolved, and the same garment with a bump: the vertices within `radius` of
// vertex `centre` moved out along the body's normal there, by `height` at the centre and less
// further off (a cone). As if the resolver had pushed a patch out on a later frame.
struct BumpedFrames {
  ResolveScene scene;
  MatrixX3d input, resolved, bumped;
  double clearance = 0;
};

BumpedFrames bumpedFrames(double height, double radius) {
  BumpedFrames b{makeWrinkledTubeScene(), MatrixX3d(), MatrixX3d(), MatrixX3d(), 0};
  const Body body(b.scene.body);
  b.input = b.scene.garment.V;
  TriMesh garment{b.input, b.scene.garment.F};
  const ResolverReport rep = resolvePenetrations(body, garment, ResolverParams());
  b.resolved = garment.V;
  b.clearance = rep.clearance;
  const int centre = static_cast<int>(b.input.rows() / 2);
  const ClosestPoint cp = closestPointOnBody(body, b.resolved.row(centre).transpose());
  const Eigen::RowVector3d n = body.faceNormals().row(cp.face);
  b.bumped = b.resolved;
  for (Eigen::Index v = 0; v < b.bumped.rows(); ++v) {
    const double d = (b.resolved.row(v) - b.resolved.row(centre)).norm();
    if (d < radius) b.bumped.row(v) += height * (1 - d / radius) * n;
  }
  return b;
}

double largestStrainAgainst(const MatrixX3d& input, const MatrixX3i& F, const MatrixX3d& V) {
  double largest = 0;
  for (Eigen::Index f = 0; f < F.rows(); ++f)
    for (int k = 0; k < 3; ++k) {
      const int a = F(f, k), b = F(f, (k + 1) % 3);
      const double l0 = (input.row(a) - input.row(b)).norm();
      largest = std::max(largest, std::abs((V.row(a) - V.row(b)).norm() / l0 - 1));
    }
  return largest;
}

}  // namespace

// Three frames of a standing body: frames 0 and 1 as resolved, frame 2 with an 8 mm bump, a jump
// that the forward pass could not hold. The backward pass spreads it over the frames before:
// frame 1 moves to within 3 mm of frame 2, then frame 0 to within 3 mm of frame 1. Frame 2 is not
// touched, every frame stays clean by the referee, and no frame is strained more than the bumped
// one, with two rings moving along (the default) or the vertices alone.
TEST(TemporalCoherence, TheBackwardPassSpreadsAJumpOverTheFramesBeforeIt) {
  const BumpedFrames b = bumpedFrames(0.008, 0.03);
  const Body body(b.scene.body);
  const MatrixX3i& F = b.scene.garment.F;
  for (const MatrixX3d* frame : {&b.resolved, &b.bumped}) {
    const ReferenceCounts c = referenceCounts(body.mesh(), TriMesh{*frame, F}, body.closed());
    ASSERT_EQ(c.garment_edge_crossings + c.body_edge_crossings + c.vertices_inside, 0u);
  }
  const double bumpStrain = largestStrainAgainst(b.input, F, b.bumped);
  for (int rings : {2, 0}) {
    std::vector<MatrixX3d> resolved{b.resolved, b.resolved, b.bumped}, inputs(3, b.input);
    std::vector<int> asked;
    auto bodyAt = [&](int k) -> const Body& {
      asked.push_back(k);
      return body;
    };
    CoherenceParams cp;
    cp.max_change = 0.003;
    cp.backward_rings = rings;
    const BackwardCoherenceReport rep =
        limitCorrectionChangeBackward(resolved, inputs, F, bodyAt, std::vector<double>(3, 0.5 * b.clearance), cp);
    ASSERT_TRUE(rep.message.empty()) << rep.message;
    EXPECT_NEAR(rep.change_before, 0.008, 1e-9);
    EXPECT_LE(rep.change_after, cp.max_change * (1 + 1e-6)) << rings;
    EXPECT_EQ(rep.frames, (std::vector<int>{1, 0}));
    EXPECT_EQ(asked, rep.frames);
    EXPECT_EQ(rep.partly + rep.held, 0u);
    EXPECT_EQ(resolved[2], b.bumped);
    for (int k = 0; k < 3; ++k) {
      const MatrixX3d& c = resolved[static_cast<std::size_t>(k)];
      if (k < 2) {
        EXPECT_LE(((resolved[k + 1] - c).rowwise().norm()).maxCoeff(), cp.max_change * (1 + 1e-6)) << k;
      }
      const ReferenceCounts counts = referenceCounts(body.mesh(), TriMesh{c, F}, body.closed());
      EXPECT_EQ(counts.garment_edge_crossings + counts.body_edge_crossings + counts.vertices_inside, 0u) << k;
    }
    const double strain = std::max(largestStrainAgainst(b.input, F, resolved[0]), largestStrainAgainst(b.input, F, resolved[1]));
    std::printf("rings %d: largest strain of frames 0 and 1 %.3f (the bumped frame %.3f)\n", rings, strain, bumpStrain);
    EXPECT_LE(strain, bumpStrain + 0.01) << rings;
  }
}

TEST(TemporalCoherence, TheBackwardPassLeavesFramesOfOtherSizesAlone) {
  const BumpedFrames b = bumpedFrames(0.008, 0.03);
  const Body body(b.scene.body);
  std::vector<MatrixX3d> resolved{b.resolved, b.bumped}, inputs{b.input, b.input.topRows(3)};
  const BackwardCoherenceReport rep = limitCorrectionChangeBackward(
      resolved, inputs, b.scene.garment.F, [&](int) -> const Body& { return body; }, {0.0, 0.0});
  EXPECT_FALSE(rep.message.empty());
  EXPECT_EQ(resolved[0], b.resolved);
  const BackwardCoherenceReport few = limitCorrectionChangeBackward(
      resolved, {b.input, b.input}, b.scene.garment.F, [&](int) -> const Body& { return body; }, {0.0});
  EXPECT_FALSE(few.message.empty());
  EXPECT_EQ(resolved[0], b.resolved);
}

// A vertex whose previous correction lies 1 cm sideways (along the body, nothing in the way):
// holding it within 3 mm of that would stretch its edges far past what the resolver left. With
// the default max_strain (0.3) it moves only as far as its edges stay within max(0.3, their
// strain as resolved), and is counted as partly moved; with max_strain 0 (no shape check) it goes
// all the way and strains an edge past that. Both frames stay clean by the referee.
TEST(TemporalCoherence, AMoveThatWouldTearAnEdgeStopsAtTheStrainLimit) {
  const ResolveScene scene = makeWrinkledTubeScene();
  const Body body(scene.body);
  const MatrixX3d input = scene.garment.V;
  TriMesh resolved{input, scene.garment.F};
  const ResolverReport rep = resolvePenetrations(body, resolved, ResolverParams());
  ASSERT_TRUE(rep.converged);
  const int v = static_cast<int>(input.rows() / 2);
  const ClosestPoint cp = closestPointOnBody(body, resolved.V.row(v).transpose());
  const Eigen::Vector3d n = body.faceNormals().row(cp.face).transpose();
  const Eigen::Vector3d side = n.unitOrthogonal();  // along the body's surface there
  MatrixX3d previous = resolved.V - input;
  previous.row(v) += 0.01 * side.transpose();
  auto strainAt = [&](const MatrixX3d& V) {  // the largest strain of v's edges against the input
    double largest = 0;
    for (Eigen::Index f = 0; f < scene.garment.F.rows(); ++f)
      for (int k = 0; k < 3; ++k) {
        const int a = scene.garment.F(f, k), b = scene.garment.F(f, (k + 1) % 3);
        if (a != v && b != v) continue;
        const double l0 = (input.row(a) - input.row(b)).norm();
        largest = std::max(largest, std::abs((V.row(a) - V.row(b)).norm() / l0 - 1));
      }
    return largest;
  };
  const double asResolved = strainAt(resolved.V);
  ASSERT_LT(asResolved, 0.3);
  CoherenceParams guarded;
  guarded.min_clearance = 0.5 * rep.clearance;
  CoherenceParams unguarded = guarded;
  unguarded.max_strain = 0;
  TriMesh kept = resolved, torn = resolved;
  const CoherenceReport k = limitCorrectionChange(body, kept, input, previous, guarded);
  const CoherenceReport t = limitCorrectionChange(body, torn, input, previous, unguarded);
  std::printf("strain at the vertex: %.3f as resolved, %.3f guarded (%zu refusals), %.3f unguarded\n", asResolved,
              strainAt(kept.V), k.strain_refusals, strainAt(torn.V));
  ASSERT_EQ(t.limited, 1u);  // the premise: without the shape check the whole move is clean
  EXPECT_GT(strainAt(torn.V), 0.4);
  EXPECT_EQ(k.candidates, 1u);
  EXPECT_EQ(k.partly, 1u);
  EXPECT_GT(k.strain_refusals, 0u);
  EXPECT_LE(strainAt(kept.V), 0.3 + 1e-9);
  EXPECT_GT(strainAt(kept.V), asResolved);  // it did move part of the way
  for (const TriMesh* g : {&kept, &torn}) {
    const ReferenceCounts c = referenceCounts(body.mesh(), *g, body.closed());
    EXPECT_EQ(c.garment_edge_crossings + c.body_edge_crossings + c.vertices_inside, 0u);
  }
}
