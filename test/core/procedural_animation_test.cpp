// The project's own animation (scenes/procedural_animation.h): the skinning leaves the legs where
// they are and turns the torso rigidly, frame 0 is the rest pose, and every frame of the waist tube
// resolved on its own frame of the body (a Body frame: refitted trees) is clean by the referee.
#include "virtual_tryon/core/body/body.h"
#include "virtual_tryon/core/resolve/penetration_resolver.h"
#include "virtual_tryon/core/scenes/procedural_animation.h"
#include "virtual_tryon/core/scenes/procedural_body.h"
#include "virtual_tryon/testing/reference_bvh.h"
#include "virtual_tryon/testing/reference_check.h"
#include "virtual_tryon/testing/reference_shape.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <string>

using namespace virtual_tryon;

TEST(ProceduralAnimation, LegsStayTheTorsoTurnsAndFrameZeroIsRest) {
  ProceduralAnimationParams p;
  p.frames = 9;
  const ProceduralAnimation a = makeProceduralAnimation(p);
  ASSERT_EQ(a.body_frames.size(), 9u);
  ASSERT_EQ(a.garment_frames.size(), 9u);
  EXPECT_LT((a.body_frames[0] - a.body.V).cwiseAbs().maxCoeff(), 1e-12);
  EXPECT_LT((a.garment_frames[0] - a.garment.V).cwiseAbs().maxCoeff(), 1e-12);
  const ProceduralBodyLandmarks L = proceduralBodyLandmarks();
  const MatrixX3d& V = a.body_frames[7];
  double legs = 0, head = 0;
  for (Eigen::Index i = 0; i < V.rows(); ++i) {
    const double moved = (V.row(i) - a.body.V.row(i)).norm();
    if (a.body.V(i, 1) < L.waist_y - p.blend) legs = std::max(legs, moved);
    if (a.body.V(i, 1) > L.neck_y) head = std::max(head, moved);
  }
  EXPECT_EQ(legs, 0.0);
  // The head turns with the torso: about (neck height above the waist) x angle.
  const double angle = proceduralSwayAngle(p, 7);
  EXPECT_NEAR(angle, p.amplitude * std::sin(2 * M_PI * 7 / 60.0), 1e-12);
  EXPECT_GT(head, 0.5 * (L.neck_y - L.waist_y) * std::abs(angle));
  // Above the blend the torso moves rigidly: distances between its vertices are kept.
  Eigen::Index a0 = -1, a1 = -1;
  for (Eigen::Index i = 0; i < V.rows() && a1 < 0; ++i)
    if (a.body.V(i, 1) > L.chest_y) (a0 < 0 ? a0 : a1) = i;
  ASSERT_GE(a1, 0);
  EXPECT_NEAR((V.row(a0) - V.row(a1)).norm(), (a.body.V.row(a0) - a.body.V.row(a1)).norm(), 1e-12);
}

TEST(ProceduralAnimation, TheDefaultClipHasNoTwoFramesAlike) {
  const ProceduralAnimation a = makeProceduralAnimation();  // as the animation bag is written
  for (std::size_t f = 1; f < a.body_frames.size(); ++f)
    EXPECT_GT((a.body_frames[f] - a.body_frames[f - 1]).cwiseAbs().maxCoeff(), 1e-4) << "frame " << f;
}

TEST(ProceduralAnimation, EveryFrameResolvesCleanOnItsRefittedBody) {
  ProceduralAnimationParams p;
  p.frames = 4;
  p.amplitude = 0.3;  // larger than the default, so that every frame moves the torso a lot
  const ProceduralAnimation a = makeProceduralAnimation(p);
  std::unique_ptr<Body> body = std::make_unique<Body>(a.body);
  for (std::size_t f = 0; f < a.body_frames.size(); ++f) {
    SCOPED_TRACE("frame " + std::to_string(f));
    if (f > 0) {
      body = std::make_unique<Body>(std::move(*body), a.body_frames[f]);
      EXPECT_TRUE(body->bvhRefitted());
    }
    TriMesh garment = a.garment;
    garment.V = a.garment_frames[f];
    const ResolverReport r = resolvePenetrations(*body, garment, ResolverParams());
    EXPECT_TRUE(r.converged) << r.reason;
    EXPECT_GT(r.garment_edge_crossings_before + r.body_edge_crossings_before, 0u);  // work to do
    TriMesh posed = a.body;
    posed.V = a.body_frames[f];
    const ReferenceCounts c = ReferenceReferee(posed).count(garment);
    EXPECT_EQ(c.garment_edge_crossings, 0u);
    EXPECT_EQ(c.body_edge_crossings, 0u);
    EXPECT_EQ(c.vertices_inside, 0u);
  }
}

namespace {

// Calls frame(body, input, f) for every frame f of `a`: the body a frame of the one before (trees
// refitted), the input the garment's frame.
template <class Frame>
void eachFrame(const ProceduralAnimation& a, Frame&& frame) {
  std::unique_ptr<Body> body = std::make_unique<Body>(a.body);
  for (std::size_t f = 0; f < a.body_frames.size(); ++f) {
    SCOPED_TRACE("frame " + std::to_string(f));
    if (f > 0) body = std::make_unique<Body>(std::move(*body), a.body_frames[f]);
    frame(*body, TriMesh{a.garment_frames[f], a.garment.F}, f);
  }
}

}  // namespace

// The garment's connectivity built once and handed to every frame's call (what the CLI and the
// node do for a sequence) gives the frames bit for bit as each call building its own; one built
// for another mesh (other counts) is not used.
TEST(ProceduralAnimation, ConnectivityBuiltOnceGivesTheSameFrames) {
  ProceduralAnimationParams p;
  p.frames = 3;
  p.amplitude = 0.3;
  const ProceduralAnimation a = makeProceduralAnimation(p);
  ResolverParams shared;
  shared.connectivity = garmentConnectivity(a.garment);
  ResolverParams wrong;
  wrong.connectivity = garmentConnectivity(a.body);
  PreviousFrame previous;
  eachFrame(a, [&](const Body& body, const TriMesh& input, std::size_t f) {
    TriMesh own = input, given = input, other = input;
    const ResolverReport r = resolveFrame(body, own, previous, ResolverParams());
    const ResolverReport g = resolveFrame(body, given, previous, shared);
    resolveFrame(body, other, previous, wrong);
    EXPECT_TRUE(r.converged) << r.reason;
    if (f == 0) EXPECT_GT(r.garment_edge_crossings_before + r.body_edge_crossings_before, 0u);  // work to do
    EXPECT_EQ(g.garment_edge_crossings_before, r.garment_edge_crossings_before);
    EXPECT_EQ(given.V, own.V);
    EXPECT_EQ(other.V, own.V);
    previous = PreviousFrame{input.V, own.V - input.V};
  });
}

namespace {

struct WarmRun {
  std::size_t relaxed = 0;  // vertices the warm frames' relaxations covered, summed
  std::size_t crossings = 0;  // in the warm frames' starts, summed
  double worst_max_strain = 0, worst_p99_strain = 0;
};

// Resolves frames 0..n-1 of `a`, each warm from the frame before (resolveFrame), and judges every
// frame by the referee on its own body against its own input.
WarmRun resolveWarm(const ProceduralAnimation& a, const ResolverParams& params) {
  WarmRun run;
  PreviousFrame previous;
  eachFrame(a, [&](const Body& body, const TriMesh& input, std::size_t f) {
    TriMesh garment = input;
    FrameStart start = FrameStart::Cold;
    const ResolverReport r = resolveFrame(body, garment, previous, params, -1, &start);
    EXPECT_TRUE(r.converged) << r.reason;
    EXPECT_EQ(start, f == 0 ? FrameStart::Cold : FrameStart::Warm);
    if (f > 0) {
      EXPECT_EQ(r.relaxation.local, params.warm_local_relaxation && !r.relaxation_widened);
      run.relaxed += r.relaxation.active_vertices;
      run.crossings += r.garment_edge_crossings_before + r.body_edge_crossings_before;
    }
    const ReferenceReferee referee(TriMesh{a.body_frames[f], a.body.F});
    const ReferenceCounts c = referee.count(garment);
    EXPECT_EQ(c.garment_edge_crossings + c.body_edge_crossings + c.vertices_inside, 0u);
    const ReferenceShape shape = referenceShape(referee, input, garment, true);
    run.worst_max_strain = std::max(run.worst_max_strain, shape.max_strain);
    run.worst_p99_strain = std::max(run.worst_p99_strain, shape.p99_strain);
    previous = PreviousFrame{input.V, garment.V - input.V};
  });
  return run;
}

}  // namespace

// A warm frame carries the frame before's corrections, so nearly every vertex starts away from its
// input; the local relaxation starts only from what the rounds moved and the edges the start
// strains, and covers far fewer vertices than the full one, with every frame as clean and about as
// little strained. The waist tube stays where it is while the torso turns in it, so that every
// warm start crosses the body again.
TEST(ProceduralAnimation, WarmFramesRelaxLocallyCleanAndAsLittleStrained) {
  ProceduralAnimationParams p;
  p.frames = 6;
  p.amplitude = 0.3;
  ProceduralAnimation a = makeProceduralAnimation(p);
  for (MatrixX3d& g : a.garment_frames) g = a.garment.V;
  ResolverParams full;
  full.warm_local_relaxation = false;
  const WarmRun fullRun = resolveWarm(a, full);
  const WarmRun localRun = resolveWarm(a, ResolverParams());
  EXPECT_GT(localRun.crossings, 0u);
  RecordProperty("crossings_local", static_cast<int>(localRun.crossings));
  RecordProperty("relaxed_local", static_cast<int>(localRun.relaxed));
  RecordProperty("relaxed_full", static_cast<int>(fullRun.relaxed));
  RecordProperty("p99_local_x1000", static_cast<int>(1000 * localRun.worst_p99_strain));
  RecordProperty("p99_full_x1000", static_cast<int>(1000 * fullRun.worst_p99_strain));
  RecordProperty("max_local_x1000", static_cast<int>(1000 * localRun.worst_max_strain));
  EXPECT_LE(localRun.worst_max_strain, 0.3);
  EXPECT_LE(localRun.worst_p99_strain, fullRun.worst_p99_strain + 0.02);
  EXPECT_LT(2 * localRun.relaxed, fullRun.relaxed) << "local " << localRun.relaxed << ", full " << fullRun.relaxed;
}

// Where the local result leaves an edge past warm_full_relaxation_strain, the relaxation runs again
// over every moved vertex (0: always), and says so.
TEST(ProceduralAnimation, ALocalRelaxationOverTheStrainLimitIsWidened) {
  ProceduralAnimationParams p;
  p.frames = 3;
  const ProceduralAnimation a = makeProceduralAnimation(p);
  ResolverParams widen;
  widen.warm_full_relaxation_strain = 0;
  const WarmRun run = resolveWarm(a, widen);
  EXPECT_GT(run.relaxed, 0u);
  std::unique_ptr<Body> body = std::make_unique<Body>(TriMesh{a.body_frames[1], a.body.F});
  TriMesh garment{a.garment_frames[1], a.garment.F};
  const PreviousFrame none{MatrixX3d(), MatrixX3d::Zero(garment.V.rows(), 3)};
  const ResolverReport r = resolveFrame(*body, garment, none, widen);
  EXPECT_TRUE(r.relaxation_widened);
  EXPECT_FALSE(r.relaxation.local);
  EXPECT_GT(r.max_edge_strain_after_local_relaxation, 0.0);
}
