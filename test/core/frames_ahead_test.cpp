// A recorded motion's frames made ready one ahead of the worn garment (core/drape/frames_ahead.h):
// the sleeveless shirt worn on the project's swaying body gives the same garment, frame by frame,
// as stepping the frames one after the other, and every frame is clean by the referee.
#include "virtual_tryon/core/body/body.h"
#include "virtual_tryon/core/drape/frames_ahead.h"
#include "virtual_tryon/core/drape/worn_garment.h"
#include "virtual_tryon/core/scenes/procedural_animation.h"
#include "virtual_tryon/testing/reference_bvh.h"
#include "virtual_tryon/testing/reference_check.h"

#include "pattern_helpers.h"

#include <gtest/gtest.h>

#include <memory>
#include <stdexcept>

using namespace virtual_tryon;
using virtual_tryon_test::proceduralPattern;

namespace {

WornGarmentParams wornParams() {
  WornGarmentParams p;
  p.drape.spacing = 0.04;
  return p;
}

// The shirt worn through the animation's frames, one frame after the other as follow(next,
// seconds) steps them: the garment's vertices per frame.
std::vector<MatrixX3d> wornOneAfterTheOther(const ProceduralAnimation& anim) {
  auto body = std::make_unique<Body>(TriMesh{anim.body_frames[0], anim.body.F});
  WornGarment worn(wornParams());
  if (!worn.dress(*body, proceduralPattern("sleeveless_shirt.yaml")).success) return {};
  std::vector<MatrixX3d> out{worn.garment().V};
  for (std::size_t f = 1; f < anim.body_frames.size(); ++f) {
    body = std::make_unique<Body>(std::move(*body), anim.body_frames[f]);
    if (!worn.follow(*body, 1.0 / anim.rate).success) break;
    out.push_back(worn.garment().V);
  }
  return out;
}

}  // namespace

TEST(FramesAhead, GivesTheFramesSteppedOneAfterTheOtherCleanEveryFrame) {
  ProceduralAnimationParams ap;
  ap.frames = 6;
  const ProceduralAnimation anim = makeProceduralAnimation(ap);
  const std::vector<MatrixX3d> expected = wornOneAfterTheOther(anim);
  ASSERT_EQ(expected.size(), anim.body_frames.size());
  for (bool ahead : {true, false}) {
    auto first = std::make_unique<Body>(TriMesh{anim.body_frames[0], anim.body.F});
    WornGarment worn(wornParams());
    ASSERT_TRUE(worn.dress(*first, proceduralPattern("sleeveless_shirt.yaml")).success);
    ASSERT_EQ(worn.garment().V, expected[0]);
    FramesAhead frames(std::move(first), anim.body_frames, worn.mapRenderer(), 1.0 / anim.rate, ahead);
    int count = 0;
    while (!frames.done()) {
      FramesAhead::Frame f = frames.next();
      ++count;
      ASSERT_EQ(f.index, count);
      ASSERT_NE(f.body, nullptr);
      EXPECT_EQ(f.body->mesh().V, anim.body_frames[static_cast<std::size_t>(f.index)]);
      EXPECT_TRUE(f.body->bvhRefitted()) << "frame " << f.index << ": the trees are refitted, not rebuilt";
      const WornFrameReport r = worn.follow(*f.body, std::move(f.maps));
      ASSERT_TRUE(r.success) << "frame " << f.index << ": " << r.message;
      EXPECT_TRUE(r.converged) << "frame " << f.index << ": " << r.message;
      EXPECT_TRUE(r.interpolated) << "frame " << f.index;
      // Bit for bit what the frames stepped one after the other gave.
      EXPECT_EQ(worn.garment().V, expected[static_cast<std::size_t>(f.index)]) << "frame " << f.index << (ahead ? " (ahead)" : "");
      const ReferenceCounts c = ReferenceReferee(f.body->mesh()).count(worn.garment());
      EXPECT_EQ(c.garment_edge_crossings + c.body_edge_crossings + c.vertices_inside, 0u) << "frame " << f.index;
    }
    EXPECT_EQ(count, ap.frames - 1);
    EXPECT_THROW(frames.next(), std::out_of_range);
  }
}

TEST(FramesAhead, AFrameOfAnotherBodyIsRefusedAndNothingHangs) {
  ProceduralAnimationParams ap;
  ap.frames = 3;
  const ProceduralAnimation anim = makeProceduralAnimation(ap);
  auto first = std::make_unique<Body>(TriMesh{anim.body_frames[0], anim.body.F});
  WornGarment worn(wornParams());
  ASSERT_TRUE(worn.dress(*first, proceduralPattern("sleeveless_shirt.yaml")).success);
  const MatrixX3d before = worn.garment().V;
  // Maps rendered for one body are not stepped against another.
  WornMapRenderer renderer = worn.mapRenderer();
  MatrixX3d more(anim.body_frames[1].rows() + 1, 3);
  more << anim.body_frames[1], anim.body_frames[1].bottomRows(1);
  const Body other(TriMesh{more, anim.body.F});  // one vertex more
  WornFrameMaps maps = renderer.render(*first, 1.0 / 30);
  const WornFrameReport r = worn.follow(other, std::move(maps));
  EXPECT_FALSE(r.success);
  EXPECT_NE(r.message.find("not rendered for this body"), std::string::npos) << r.message;
  EXPECT_EQ(worn.garment().V, before);
  // A frame of another vertex count: next() rethrows the body's refusal; the destructor returns.
  std::vector<MatrixX3d> frames = anim.body_frames;
  frames[1] = frames[1].topRows(frames[1].rows() - 1).eval();
  for (bool ahead : {true, false}) {
    FramesAhead bad(std::make_unique<Body>(TriMesh{anim.body_frames[0], anim.body.F}), frames, worn.mapRenderer(),
                    1.0 / 30, ahead);
    EXPECT_THROW(bad.next(), std::invalid_argument);
  }
}
