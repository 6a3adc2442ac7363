// A garment worn on a moving body (core/drape/worn_garment.h): the sleeveless shirt draped on the
// project's swaying body (scenes/procedural_animation.h) and stepped through its frames, every frame
// checked by the independent referee; the trousers through a stride of the legs; the frames made
// ready ahead on a second thread; and what the worn garment refuses.
#include "virtual_tryon/core/body/body.h"
#include "virtual_tryon/core/drape/frames_ahead.h"
#include "virtual_tryon/core/drape/worn_garment.h"
#include "virtual_tryon/core/io/pattern_yaml.h"
#include "virtual_tryon/core/scenes/procedural_animation.h"
#include "virtual_tryon/core/scenes/procedural_body.h"
#include "virtual_tryon/testing/reference_bvh.h"
#include "virtual_tryon/testing/reference_check.h"

#include "pattern_helpers.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <memory>
#include <stdexcept>
#include <string>

using namespace virtual_tryon;
using virtual_tryon_test::proceduralPattern;

namespace {


WornGarmentParams wornParams() {
  WornGarmentParams p;
  p.drape.spacing = 0.04;
  return p;
}

// The vertices above height y.
std::vector<Eigen::Index> above(const MatrixX3d& V, double y) {
  std::vector<Eigen::Index> idx;
  for (Eigen::Index i = 0; i < V.rows(); ++i)
    if (V(i, 1) > y) idx.push_back(i);
  return idx;
}

// For each of the points idx of P, the nearest vertex of V.
std::vector<Eigen::Index> nearestOf(const MatrixX3d& V, const MatrixX3d& P, const std::vector<Eigen::Index>& idx) {
  std::vector<Eigen::Index> out;
  for (Eigen::Index i : idx) {
    Eigen::Index best = 0;
    (V.rowwise() - P.row(i)).rowwise().squaredNorm().minCoeff(&best);
    out.push_back(best);
  }
  return out;
}

Eigen::RowVector3d meanOf(const MatrixX3d& V, const std::vector<Eigen::Index>& idx) {
  Eigen::RowVector3d sum = Eigen::RowVector3d::Zero();
  for (Eigen::Index i : idx) sum += V.row(i);
  return idx.empty() ? sum : Eigen::RowVector3d(sum / static_cast<double>(idx.size()));
}

// The procedural body's first frame and that body moved rigidly by `shift` (m) 1/30 s later; the
// sleeveless shirt draped on the first and stepped to the second, without the skin-carried
// fallback (plain) and with it (carried).
struct WithAndWithoutCarry {
  std::unique_ptr<Body> first, moved;
  std::unique_ptr<WornGarment> plain, carried;
  WornFrameReport a, b;  // plain's frame, carried's frame
};

WithAndWithoutCarry stepWithAndWithoutCarry(const Eigen::RowVector3d& shift) {
  ProceduralAnimationParams ap;
  ap.frames = 1;
  const ProceduralAnimation anim = makeProceduralAnimation(ap);
  WithAndWithoutCarry r;
  r.first = std::make_unique<Body>(TriMesh{anim.body_frames[0], anim.body.F});
  r.moved = std::make_unique<Body>(*r.first, MatrixX3d(anim.body_frames[0].rowwise() + shift));
  WornGarmentParams off = wornParams();
  off.carry_with_skin = false;
  r.plain = std::make_unique<WornGarment>(off);
  r.carried = std::make_unique<WornGarment>(wornParams());
  for (WornGarment* w : {r.plain.get(), r.carried.get()})
    if (!w->dress(*r.first, proceduralPattern("sleeveless_shirt.yaml")).success) return r;
  r.a = r.plain->follow(*r.moved, 1.0 / 30);
  r.b = r.carried->follow(*r.moved, 1.0 / 30);
  return r;
}

// The procedural body swaying for `frames` frames.
ProceduralAnimation swaying(int frames) {
  ProceduralAnimationParams ap;
  ap.frames = frames;
  return makeProceduralAnimation(ap);
}

// The shirt worn through the animation's frames, one frame after the other as follow(next,
// seconds) steps them: the garment's vertices per frame, and (from frame 1) each frame's report
// with the referee's counts.
struct WornFrames {
  std::vector<MatrixX3d> V;
  std::vector<WornFrameReport> reports;
  std::vector<ReferenceCounts> counts;
};

WornFrames wornFrames(const ProceduralAnimation& anim, const WornGarmentParams& params) {
  auto body = std::make_unique<Body>(TriMesh{anim.body_frames[0], anim.body.F});
  WornGarment worn(params);
  WornFrames out;
  if (!worn.dress(*body, proceduralPattern("sleeveless_shirt.yaml")).success) return out;
  out.V.push_back(worn.garment().V);
  for (std::size_t f = 1; f < anim.body_frames.size(); ++f) {
    body = std::make_unique<Body>(std::move(*body), anim.body_frames[f]);
    out.reports.push_back(worn.follow(*body, 1.0 / anim.rate));
    if (!out.reports.back().success) break;
    out.V.push_back(worn.garment().V);
    out.counts.push_back(ReferenceReferee(body->mesh()).count(worn.garment()));
  }
  return out;
}

std::vector<MatrixX3d> wornOneAfterTheOther(const ProceduralAnimation& anim) { return wornFrames(anim, wornParams()).V; }

}  // namespace

TEST(WornGarment, TheShirtFollowsTheSwayingTorsoCleanEveryFrame) {
  ProceduralAnimationParams ap;
  ap.frames = 10;
  const ProceduralAnimation anim = makeProceduralAnimation(ap);
  auto body = std::make_unique<Body>(TriMesh{anim.body_frames[0], anim.body.F});
  WornGarment worn(wornParams());
  const DrapeResult dressed = worn.dress(*body, proceduralPattern("sleeveless_shirt.yaml"));
  ASSERT_TRUE(dressed.success) << dressed.message;
  ASSERT_TRUE(worn.worn());
  // The frames step at dt_safety of the cloth's own stability limit, well above the per-node bound
  // the drape steps at, within the collision shell's bound and at least the drape's step.
  const WornGarmentParams& wp = worn.params();
  EXPECT_GT(worn.stepLimit(), 1.3 * dressed.dt_bound);
  EXPECT_DOUBLE_EQ(worn.clothStep(), std::max(dressed.dt, std::min(wp.dt_safety * worn.stepLimit(),
                                                                   wp.drape.collision.tol / WornGarment::kMaxSurfaceSpeed)));
  EXPECT_GT(worn.clothStep(), 1.1 * dressed.dt);
  const ProceduralBodyLandmarks L = proceduralBodyLandmarks();
  const std::vector<Eigen::Index> shirtTop = above(worn.garment().V, L.chest_y);
  const std::vector<Eigen::Index> bodyTop = nearestOf(body->mesh().V, worn.garment().V, shirtTop);
  ASSERT_GT(shirtTop.size(), 10u);
  const Eigen::RowVector3d shirtStart = meanOf(worn.garment().V, shirtTop);
  const Eigen::RowVector3d bodyStart = meanOf(body->mesh().V, bodyTop);
  for (int f = 1; f < ap.frames; ++f) {
    body = std::make_unique<Body>(std::move(*body), anim.body_frames[static_cast<std::size_t>(f)]);
    const WornFrameReport r = worn.follow(*body, 1.0 / anim.rate);
    ASSERT_TRUE(r.success) << "frame " << f << ": " << r.message;
    EXPECT_TRUE(r.converged) << "frame " << f << ": " << r.message;
    EXPECT_TRUE(r.interpolated) << "frame " << f;
    EXPECT_FALSE(r.grid_rebuilt) << "frame " << f;
    EXPECT_GT(r.steps, 0);
    EXPECT_NEAR(r.steps * r.dt, 1.0 / anim.rate, 1e-12);
    EXPECT_EQ(r.steps, static_cast<int>(std::ceil(1.0 / anim.rate / worn.clothStep() - 1e-9))) << "frame " << f;
    EXPECT_TRUE(r.resolver_run);
    EXPECT_LT(r.max_speed, 5.0) << "frame " << f;  // no blow-up: the torso moves at well under 1 m/s
    const TriMesh& g = worn.garment();
    ASSERT_TRUE(g.V.allFinite());
    const ReferenceCounts c = ReferenceReferee(body->mesh()).count(g);  // = referenceCounts, with a tree
    EXPECT_EQ(c.garment_edge_crossings, 0u) << "frame " << f;
    EXPECT_EQ(c.body_edge_crossings, 0u) << "frame " << f;
    EXPECT_EQ(c.vertices_inside, 0u) << "frame " << f;
    EXPECT_LE(r.strain_max, 0.15) << "frame " << f;
    const double vertexStrain = *std::max_element(worn.vertexStrain().begin(), worn.vertexStrain().end());
    EXPECT_NEAR(vertexStrain, r.strain_max, 1e-12);
  }
  // The shirt's top went with the body under it (which moved by over a centimetre): at least half
  // the way, and off its direction by less than half (a loose shirt lags by its ease).
  const Eigen::RowVector3d bodyMove = meanOf(body->mesh().V, bodyTop) - bodyStart;
  const Eigen::RowVector3d shirtMove = meanOf(worn.garment().V, shirtTop) - shirtStart;
  ASSERT_GT(bodyMove.norm(), 0.01);
  EXPECT_GT(shirtMove.dot(bodyMove.normalized()), bodyMove.norm() / 2) << "body " << bodyMove << ", shirt " << shirtMove;
  EXPECT_LT((shirtMove - bodyMove).norm(), bodyMove.norm() / 2) << "body " << bodyMove << ", shirt " << shirtMove;
}

TEST(WornGarment, RefusesWhatItCannotStep) {
  const Body body(makeProceduralBody());
  WornGarment idle(wornParams());
  WornFrameReport r = idle.follow(body, 1.0 / 30);
  EXPECT_FALSE(r.success);
  EXPECT_NE(r.message.find("dress"), std::string::npos) << r.message;

  WornGarmentParams objectSpace = wornParams();
  objectSpace.drape.mode = CollisionMode::ObjectSpace;
  WornGarment object(objectSpace);
  const DrapeResult d = object.dress(body, proceduralPattern("skirt.yaml"));
  EXPECT_FALSE(d.success);
  EXPECT_NE(d.message.find("image space"), std::string::npos) << d.message;
  EXPECT_FALSE(object.worn());

  for (double safety : {0.0, -0.5, 1.5, std::nan("")}) {
    WornGarmentParams bad = wornParams();
    bad.dt_safety = safety;
    WornGarment refused(bad);
    const DrapeResult dr = refused.dress(body, proceduralPattern("skirt.yaml"));
    EXPECT_FALSE(dr.success) << safety;
    EXPECT_NE(dr.message.find("dt_safety"), std::string::npos) << dr.message;
  }

  // A step above the cloth's stability limit is refused once the limit is known (after the drape).
  WornGarmentParams tooLong = wornParams();
  tooLong.dt = 0.01;
  WornGarment unstable(tooLong);
  const DrapeResult dl = unstable.dress(body, proceduralPattern("skirt.yaml"));
  EXPECT_FALSE(dl.success);
  EXPECT_NE(dl.message.find("stability limit"), std::string::npos) << dl.message;
  EXPECT_FALSE(unstable.worn());
  EXPECT_FALSE(unstable.follow(body, 1.0 / 30).success);

  WornGarmentParams fewSteps = wornParams();
  fewSteps.max_steps_per_frame = 2;
  WornGarment worn(fewSteps);
  ASSERT_TRUE(worn.dress(body, proceduralPattern("skirt.yaml")).success);
  const TriMesh before = worn.garment();
  for (double seconds : {0.0, -1.0, std::nan("")}) {
    r = worn.follow(body, seconds);
    EXPECT_FALSE(r.success) << seconds;
    EXPECT_NE(r.message.find("positive"), std::string::npos) << r.message;
  }
  r = worn.follow(body, 10.0);  // far more than two steps
  EXPECT_FALSE(r.success);
  EXPECT_NE(r.message.find("max_steps_per_frame"), std::string::npos) << r.message;
  EXPECT_EQ(worn.garment().V, before.V);  // nothing moved
}

// A jerk: the torso, swaying twice as far as the default clip, jumps from its first frame to its
// last (a 14 degree bend) in one 30 Hz interval. The correction of that frame leaves the shirt
// strained past max_strain; relaxed and resolved again, the shirt that is kept is clean by the
// referee and less strained than the first correction left it (which --no-resolve-relaxed keeps).
TEST(WornGarment, ASpikedFrameIsRelaxedResolvedAgainAndKeptWhenLessStrained) {
  ProceduralAnimationParams ap;
  ap.frames = 10;
  ap.amplitude = 0.3;  // rad: about 17 degrees, twice the default clip's bend
  const ProceduralAnimation anim = makeProceduralAnimation(ap);
  const Body first(TriMesh{anim.body_frames[0], anim.body.F});
  const Body last(TriMesh{anim.body_frames.back(), anim.body.F});
  WornGarmentParams off = wornParams();
  off.resolve_relaxed = false;
  off.carry_with_skin = false;  // the first correction as it is (the fallback would take it: 0.140)
  WornGarment plain(off), relaxed(wornParams());
  ASSERT_TRUE(plain.dress(first, proceduralPattern("sleeveless_shirt.yaml")).success);
  ASSERT_TRUE(relaxed.dress(first, proceduralPattern("sleeveless_shirt.yaml")).success);
  const WornFrameReport a = plain.follow(last, 1.0 / 30);
  const WornFrameReport b = relaxed.follow(last, 1.0 / 30);
  ASSERT_TRUE(a.success) << a.message;
  ASSERT_TRUE(b.success) << b.message;
  std::printf("jerk: first correction strain %.3f (%d relax passes); relaxed and resolved again %.3f (%s)\n",
              a.strain_max, a.relax_passes, b.strain_max, b.resolved_relaxed ? "kept" : "not kept");
  // The premise: the first correction spiked the shirt.
  ASSERT_GT(a.strain_max, wornParams().drape.max_strain) << a.message;
  EXPECT_FALSE(a.resolved_relaxed);
  ASSERT_TRUE(b.resolved_relaxed) << b.message;
  EXPECT_LT(b.strain_max, a.strain_max);
  EXPECT_TRUE(b.relaxed_resolver.converged) << b.relaxed_resolver.reason;
  EXPECT_NE(b.message.find("resolved again"), std::string::npos) << b.message;
  const ReferenceReferee referee(last.mesh());
  for (const WornGarment* w : {&plain, &relaxed}) {
    const ReferenceCounts c = referee.count(w->garment());
    EXPECT_EQ(c.garment_edge_crossings + c.body_edge_crossings + c.vertices_inside, 0u);
  }
  const double vertexStrain = *std::max_element(relaxed.vertexStrain().begin(), relaxed.vertexStrain().end());
  EXPECT_NEAR(vertexStrain, b.strain_max, 1e-12);
}

// A body that leaps further in one frame than the steps can follow: the steps' correction cannot
// undo it, and the last clean cloth carried with the skin (each node as its nearest body vertex
// moved) is corrected instead. Without the fallback the frame is left crossed. The leap is 17 cm in
// 1/30 s (5.1 m/s, beyond the surface speed the collisions take): at 13 cm the frames' longer
// steps (the spectral bound) followed it, strained but uncrossed.
TEST(WornGarment, AFrameTheStepsCannotFollowIsCarriedWithTheSkin) {
  const WithAndWithoutCarry run = stepWithAndWithoutCarry(Eigen::RowVector3d(0.16, 0, 0.06));  // m in 1/30 s
  const Body& away = *run.moved;
  const WornGarment &plain = *run.plain, &carried = *run.carried;
  const WornFrameReport &a = run.a, &b = run.b;
  ASSERT_TRUE(a.success) << a.message;
  ASSERT_TRUE(b.success) << b.message;
  std::printf("leap: steps' correction %s (%zu crossings left); carried %s (%s), strain %.3f\n",
              a.resolver.converged ? "converged" : "failed",
              a.resolver.garment_edge_crossings_after + a.resolver.body_edge_crossings_after,
              b.carried ? (b.carried_whole ? "whole" : "around the crossings") : "no", b.message.c_str(), b.strain_max);
  const ReferenceReferee referee(away.mesh());
  const ReferenceCounts ca = referee.count(plain.garment()), cb = referee.count(carried.garment());
  // The premise: the steps alone leave the leapt body crossed.
  ASSERT_FALSE(a.resolver.converged);
  ASSERT_GT(ca.garment_edge_crossings + ca.body_edge_crossings + ca.vertices_inside, 0u);
  ASSERT_TRUE(b.carried) << b.message;
  EXPECT_EQ(b.carried_from, 1);
  EXPECT_FALSE(b.stepped_resolver.converged);
  EXPECT_EQ(cb.garment_edge_crossings + cb.body_edge_crossings + cb.vertices_inside, 0u);
  EXPECT_NE(b.message.find("carried with the skin"), std::string::npos) << b.message;
  EXPECT_LT(b.strain_max, 0.3);
  // The next frame goes on from the carried cloth.
  MatrixX3d further = away.mesh().V;
  further.col(0).array() += 0.002;
  const Body next(away, further);
  const WornFrameReport c = run.carried->follow(next, 1.0 / 30);
  ASSERT_TRUE(c.success) << c.message;
  const ReferenceCounts cc = ReferenceReferee(next.mesh()).count(carried.garment());
  EXPECT_EQ(cc.garment_edge_crossings + cc.body_edge_crossings + cc.vertices_inside, 0u) << c.message;
}

// A body lifted 8 cm in one 30 Hz frame: the steps' correction converges but leaves the shirt
// strained past max_strain (the cloth lagging below the shoulders), and the relaxed second resolve
// does not bring it back; the last clean cloth carried with the skin is less strained and kept.
TEST(WornGarment, AFrameLeftStrainedIsCarriedWithTheSkinWhenThatIsLessStrained) {
  const WithAndWithoutCarry run = stepWithAndWithoutCarry(Eigen::RowVector3d(0, 0.08, 0));
  const Body& up = *run.moved;
  const WornGarment& carried = *run.carried;
  const WornFrameReport &a = run.a, &b = run.b;
  ASSERT_TRUE(a.success) << a.message;
  ASSERT_TRUE(b.success) << b.message;
  std::printf("lift: strain %.3f without the fallback, %.3f carried (%s)\n", a.strain_max, b.strain_max, b.message.c_str());
  // The premise: the steps and their corrections leave a spring past max_strain.
  ASSERT_TRUE(a.resolver.converged || a.resolved_relaxed) << a.message;
  ASSERT_GT(a.strain_max, wornParams().drape.max_strain);
  EXPECT_FALSE(a.converged);
  ASSERT_TRUE(b.carried) << b.message;
  EXPECT_TRUE(b.carried_for_strain);
  EXPECT_NEAR(b.stepped_strain_max, a.strain_max, 1e-12);
  EXPECT_LE(b.strain_max, wornParams().drape.max_strain);
  EXPECT_TRUE(b.converged) << b.message;
  EXPECT_NE(b.message.find("carried with the skin"), std::string::npos) << b.message;
  const ReferenceCounts c = ReferenceReferee(up.mesh()).count(carried.garment());
  EXPECT_EQ(c.garment_edge_crossings + c.body_edge_crossings + c.vertices_inside, 0u);
  const double vertexStrain = *std::max_element(carried.vertexStrain().begin(), carried.vertexStrain().end());
  EXPECT_NEAR(vertexStrain, b.strain_max, 1e-12);
}

// A recorded motion's frames made ready one ahead of the worn garment (core/drape/frames_ahead.h):
// the same garment, frame by frame, as stepping the frames one after the other.
// Each frame is first corrected with the quick relaxation where its steps left the cloth within
// quick_strain, and that is kept only when it stays within it (else the drape's relaxation). Every
// frame is clean by the referee either way; with quick_strain below every frame's steps' strain the
// quick one is never tried, and the frames are those of quick_sweeps = 0 bit for bit.
TEST(WornGarment, AQuickCorrectionIsKeptOnlyWhereItStaysWithinItsStrain) {
  const ProceduralAnimation anim = swaying(6);
  const WornGarmentParams params = wornParams();
  ASSERT_GT(params.quick_sweeps, 0);
  const WornFrames quick = wornFrames(anim, params);
  ASSERT_EQ(quick.V.size(), anim.body_frames.size());
  int kept = 0;
  for (std::size_t f = 0; f < quick.reports.size(); ++f) {
    const WornFrameReport& r = quick.reports[f];
    const ReferenceCounts& c = quick.counts[f];
    EXPECT_EQ(c.garment_edge_crossings + c.body_edge_crossings + c.vertices_inside, 0u) << "frame " << f + 1;
    EXPECT_TRUE(r.converged) << "frame " << f + 1 << ": " << r.message;
    if (!r.quick_correction) continue;
    ++kept;
    EXPECT_LE(r.strain_stepped, params.quick_strain) << "frame " << f + 1;
    EXPECT_LE(r.strain_max, params.quick_strain) << "frame " << f + 1;
  }
  EXPECT_GT(kept, 0);  // the premise: the swaying shirt's frames are mostly quick
  WornGarmentParams never = params, off = params;
  never.quick_strain = 1e-9;
  off.quick_sweeps = 0;
  const WornFrames a = wornFrames(anim, never), b = wornFrames(anim, off);
  ASSERT_EQ(a.V.size(), anim.body_frames.size());
  ASSERT_EQ(b.V.size(), a.V.size());
  for (std::size_t f = 0; f < a.V.size(); ++f) EXPECT_EQ(a.V[f], b.V[f]) << "frame " << f;
  for (const WornFrameReport& r : a.reports) EXPECT_FALSE(r.quick_correction);
}

TEST(FramesAhead, GivesTheFramesSteppedOneAfterTheOtherCleanEveryFrame) {
  const ProceduralAnimation anim = swaying(6);
  const std::vector<MatrixX3d> expected = wornOneAfterTheOther(anim);
  ASSERT_EQ(expected.size(), anim.body_frames.size());
  // Made ahead once the garment is worn, one after the other, and ahead from the start of the
  // drape on (frame 1 made ready while the first frame is draped: dress's mapsReady).
  for (const char* mode : {"ahead", "one ahead", "one after the other", "ahead from the drape"}) {
    const bool ahead = std::string(mode) != "one after the other", fromDrape = std::string(mode) == "ahead from the drape";
    const int depth = std::string(mode) == "one ahead" ? 1 : FramesAhead::kDefaultDepth;
    auto first = std::make_unique<Body>(TriMesh{anim.body_frames[0], anim.body.F});
    const Body& body0 = *first;
    WornGarment worn(wornParams());
    std::unique_ptr<FramesAhead> made;
    const auto start = [&](const WornMapRenderer& renderer) {
      made = std::make_unique<FramesAhead>(std::move(first), anim.body_frames, renderer, 1.0 / anim.rate, ahead, depth);
    };
    ASSERT_TRUE(worn.dress(body0, proceduralPattern("sleeveless_shirt.yaml"), nullptr, 25,
                           fromDrape ? std::function<void(const WornMapRenderer&)>(start) : nullptr)
                    .success);
    ASSERT_EQ(worn.garment().V, expected[0]);
    if (!fromDrape) start(worn.mapRenderer());
    ASSERT_TRUE(made);
    FramesAhead& frames = *made;
    int count = 0;
    while (!frames.done()) {
      FramesAhead::Frame f = frames.next();
      ++count;
      ASSERT_EQ(f.index, count);
      ASSERT_NE(f.body, nullptr);
      EXPECT_EQ(f.body->mesh().V, anim.body_frames[static_cast<std::size_t>(f.index)]);
      EXPECT_GE(f.queued, 0);
      EXPECT_LE(f.queued, ahead ? depth - 1 : 0) << "frame " << f.index << " (" << mode << ")";
      EXPECT_TRUE(f.body->bvhRefitted()) << "frame " << f.index << " (" << mode << "): the trees are refitted, not rebuilt";
      const WornFrameReport r = worn.follow(*f.body, std::move(f.maps));
      ASSERT_TRUE(r.success) << "frame " << f.index << ": " << r.message;
      EXPECT_TRUE(r.converged) << "frame " << f.index << ": " << r.message;
      EXPECT_TRUE(r.interpolated) << "frame " << f.index;
      // Bit for bit what the frames stepped one after the other gave.
      EXPECT_EQ(worn.garment().V, expected[static_cast<std::size_t>(f.index)]) << "frame " << f.index << " (" << mode << ")";
      const ReferenceCounts c = ReferenceReferee(f.body->mesh()).count(worn.garment());
      EXPECT_EQ(c.garment_edge_crossings + c.body_edge_crossings + c.vertices_inside, 0u) << "frame " << f.index;
    }
    EXPECT_EQ(count, 5);
    EXPECT_THROW(frames.next(), std::out_of_range);
  }
}

TEST(FramesAhead, AFrameOfAnotherBodyIsRefusedAndNothingHangs) {
  const ProceduralAnimation anim = swaying(3);
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
    EXPECT_THROW(bad.next(), std::invalid_argument);  // again, instead of waiting for frames never made
  }
  // Left with frames made and waiting (the second thread held back by the full queue): the
  // destructor stops it and returns.
  {
    FramesAhead unused(std::make_unique<Body>(TriMesh{anim.body_frames[0], anim.body.F}), anim.body_frames,
                       worn.mapRenderer(), 1.0 / 30, true, 1);
  }
  EXPECT_THROW(FramesAhead(std::make_unique<Body>(TriMesh{anim.body_frames[0], anim.body.F}), anim.body_frames,
                           worn.mapRenderer(), 1.0 / 30, true, 0),
               std::invalid_argument);
}

namespace {

// The procedural body's legs swung from the hips, as a stride: the left leg (x > 0) turned
// forward and the right one back by `angle` (rad) about the x axis through the hip joints; each
// vertex's weight rises smoothly from 0 a thigh radius above the hip joints to 1 a thigh radius
// below them, and from 0 at the body's middle (x = 0) to 1 a third of a thigh radius to the side,
// so that the crotch between the legs bends instead of tearing.
MatrixX3d swungLegs(const MatrixX3d& V, double angle) {
  const ProceduralBodyLandmarks L = proceduralBodyLandmarks();
  const double r = L.thigh_radius, hipY = L.left_hip_joint.y(), hipZ = L.left_hip_joint.z();
  auto smooth = [](double t) {
    t = std::clamp(t, 0.0, 1.0);
    return t * t * (3 - 2 * t);
  };
  MatrixX3d out = V;
  for (Eigen::Index i = 0; i < V.rows(); ++i) {
    const double x = V(i, 0), y = V(i, 1), z = V(i, 2);
    const double w = smooth((hipY + r - y) / (2 * r)) * smooth(std::abs(x) / (r / 3));
    if (!(w > 0)) continue;
    const double a = (x > 0 ? -angle : angle) * w;  // about +x, a negative turn swings the foot forward (+z)
    const double dy = y - hipY, dz = z - hipZ;
    out(i, 1) = hipY + std::cos(a) * dy - std::sin(a) * dz;
    out(i, 2) = hipZ + std::sin(a) * dy + std::cos(a) * dz;
  }
  return out;
}

// The procedural trousers worn through `frames` frames (30 Hz) of a stride that swings the legs
// from 0 to +-amplitude and back (a sine over `period` s); per frame the report and the referee's
// counts.
struct Stride {
  DrapeResult dressed;
  std::vector<WornFrameReport> reports;
  std::vector<ReferenceCounts> counts;
};

Stride trousersThroughAStride(const WornGarmentParams& params, int frames, double amplitude, double period) {
  const TriMesh rest = makeProceduralBody();
  auto body = std::make_unique<Body>(rest);
  WornGarment worn(params);
  Stride s;
  s.dressed = worn.dress(*body, proceduralPattern("trousers.yaml"));
  if (!s.dressed.success) return s;
  for (int f = 1; f < frames; ++f) {
    const double angle = amplitude * std::sin(2 * M_PI * f / (30.0 * period));
    body = std::make_unique<Body>(std::move(*body), swungLegs(rest.V, angle));
    s.reports.push_back(worn.follow(*body, 1.0 / 30));
    if (!s.reports.back().success) break;
    s.counts.push_back(ReferenceReferee(body->mesh()).count(worn.garment()));
  }
  return s;
}

}  // namespace

// A stride the trousers' cloth follows by its own steps: the legs swing to +-34 degrees (the
// walk's hips swing +-25), the trousers worn through the 16 frames up to that, every frame clean by
// the referee, within 0.15 and not carried with the skin. With shear springs of 2 N/m (the default
// before 20) their cells sheared out of the legs' way: 2 frames of this stride fell back to the
// skin-carried cloth, and at +-37 degrees 9, one of them over 0.15.
TEST(WornGarment, TrousersFollowAStrideCleanAndWithinStrainEveryFrame) {
  const Stride s = trousersThroughAStride(wornParams(), 16, 0.6, 2.0);
  ASSERT_TRUE(s.dressed.success) << s.dressed.message;
  ASSERT_EQ(s.reports.size(), 15u);
  ASSERT_EQ(s.counts.size(), 15u);
  for (std::size_t i = 0; i < s.reports.size(); ++i) {
    const WornFrameReport& r = s.reports[i];
    const int f = static_cast<int>(i) + 1;
    EXPECT_TRUE(r.converged) << "frame " << f << ": " << r.message;
    EXPECT_LE(r.strain_max, 0.15) << "frame " << f;
    EXPECT_FALSE(r.carried) << "frame " << f << ": " << r.message;
    EXPECT_LT(r.max_speed, 5.0) << "frame " << f;
    EXPECT_EQ(s.counts[i].garment_edge_crossings, 0u) << "frame " << f;
    EXPECT_EQ(s.counts[i].body_edge_crossings, 0u) << "frame " << f;
    EXPECT_EQ(s.counts[i].vertices_inside, 0u) << "frame " << f;
  }
}
