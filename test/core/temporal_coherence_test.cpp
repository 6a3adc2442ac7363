// limitCorrectionChange (core/resolve/temporal_coherence.h) on the project's wrinkled tube scene moved
// a little every frame (rounded to float, as a point cache holds it: enough to change some of the
// resolver's decisions), every frame resolved on its own. Bringing each correction's change within
// the limit keeps every frame clean by the independent referee.
#include "virtual_tryon/core/body/body.h"
#include "virtual_tryon/core/resolve/penetration_resolver.h"
#include "virtual_tryon/core/resolve/temporal_coherence.h"
#include "virtual_tryon/core/scenes/procedural.h"
#include "virtual_tryon/core/scenes/procedural_animation.h"
#include "virtual_tryon/testing/reference_check.h"

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
