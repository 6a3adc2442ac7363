// The project's own animation (scenes/procedural_animation.h): the skinning leaves the legs where
// they are and turns the torso rigidly, frame 0 is the rest pose, and every frame of the waist tube
// resolved on its own frame of the body (a Body frame: refitted trees) is clean by the referee.
#include "virtual_tryon/core/body/body.h"
#include "virtual_tryon/core/resolve/penetration_resolver.h"
#include "virtual_tryon/core/scenes/procedural_animation.h"
#include "virtual_tryon/core/scenes/procedural_body.h"
#include "virtual_tryon/testing/reference_bvh.h"
#include "virtual_tryon/testing/reference_check.h"

#include <gtest/gtest.h>

#include <cmath>
#include <memory>

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
