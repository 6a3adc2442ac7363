// Point Cache 2: round trip, every refusal (before allocation where a size is declared), and
// tryon animate resolve on a small moving scene of the project's own.
#include "virtual_tryon/core/drape/frames_ahead.h"
#include "virtual_tryon/core/drape/worn_garment.h"
#include "virtual_tryon/core/io/mesh_io.h"
#include "virtual_tryon/core/io/point_cache.h"
#include "virtual_tryon/core/scenes/procedural.h"
#include "virtual_tryon/core/scenes/procedural_animation.h"

#include "test_helpers.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <fstream>
#include <limits>
#include <regex>
#include <sstream>
#include <vector>

using namespace virtual_tryon;
using namespace virtual_tryon_test;

namespace {

PointCache smallCache() {
  PointCache c;
  c.points = 3;
  c.start_frame = 2;
  c.sample_rate = 1;
  for (int s = 0; s < 4; ++s) {
    MatrixX3d X(3, 3);
    for (int i = 0; i < 3; ++i) X.row(i) = Eigen::RowVector3d(0.25 * i, 0.5 * s, -1.0 + i * s);
    c.samples.push_back(X);
  }
  return c;
}

std::string errorOf(const std::string& bytes, int expect = -1, const PointCacheLimits& limits = PointCacheLimits()) {
  PointCache c;
  std::string err;
  EXPECT_FALSE(parsePointCache(bytes, c, err, expect, limits));
  EXPECT_FALSE(err.empty());
  return err;
}

void setInt(std::string& bytes, std::size_t at, std::int32_t v) { std::memcpy(&bytes[at], &v, 4); }  // little-endian host

}  // namespace

TEST(PointCache, RoundTripsExactlyForFloatValues) {
  const PointCache c = smallCache();
  const std::string bytes = pointCacheBytes(c);
  EXPECT_EQ(bytes.size(), 32u + 4 * 3 * 12);
  EXPECT_EQ(bytes.substr(0, 12), std::string("POINTCACHE2\0", 12));
  PointCache back;
  std::string err;
  ASSERT_TRUE(parsePointCache(bytes, back, err, 3)) << err;
  EXPECT_EQ(back.points, 3);
  EXPECT_EQ(back.start_frame, 2.0f);
  ASSERT_EQ(back.samples.size(), 4u);
  for (int s = 0; s < 4; ++s) EXPECT_EQ(back.samples[s], c.samples[s]);
  const std::string dir = tempDir("pc2");
  ASSERT_TRUE(writePointCache(dir + "/c.pc2", c, err)) << err;
  ASSERT_TRUE(readPointCache(dir + "/c.pc2", back, err)) << err;
  EXPECT_EQ(back.samples[3], c.samples[3]);
}

TEST(PointCache, RefusesWhatDoesNotAddUp) {
  const std::string good = pointCacheBytes(smallCache());
  EXPECT_TRUE(contains(errorOf("POINTCACHE2"), "shorter than the 32-byte header"));
  std::string bad = good;
  bad[0] = 'X';
  EXPECT_TRUE(contains(errorOf(bad), "signature"));
  bad = good;
  setInt(bad, 12, 2);
  EXPECT_TRUE(contains(errorOf(bad), "version 2"));
  EXPECT_TRUE(contains(errorOf(good.substr(0, good.size() - 4)), "truncated"));
  EXPECT_TRUE(contains(errorOf(good + "xx"), "trailing bytes"));
  EXPECT_TRUE(contains(errorOf(good, 4), "3 points, the mesh 4 vertices"));
  bad = good;
  setInt(bad, 16, -1);
  EXPECT_TRUE(contains(errorOf(bad), "negative"));
  // A declared size far beyond the bytes and the limits is refused from the header alone.
  bad = good;
  setInt(bad, 16, 2000000000);
  EXPECT_TRUE(contains(errorOf(bad), "over the limits"));
  PointCacheLimits tight;
  tight.max_samples = 3;
  EXPECT_TRUE(contains(errorOf(good, -1, tight), "over the limits"));
  bad = good;
  const float nan = std::numeric_limits<float>::quiet_NaN();
  std::memcpy(&bad[32 + 36 + 4], &nan, 4);  // sample 1 (36 bytes on), point 0, y
  EXPECT_TRUE(contains(errorOf(bad), "sample 1, point 0 is not finite"));
  PointCache c;
  std::string err;
  EXPECT_FALSE(readPointCache("/nonexistent/a.pc2", c, err));
  EXPECT_TRUE(contains(err, "/nonexistent/a.pc2"));
  PointCache wrong = smallCache();
  wrong.samples[2].conservativeResize(2, 3);
  EXPECT_FALSE(writePointCache(tempDir("pc2w") + "/w.pc2", wrong, err));
  EXPECT_TRUE(contains(err, "sample 2"));
}

// The wrinkled tube scene moved rigidly over 5 frames: every frame resolved on its own, clean by the
// referee, and the correction moves with the scene within the moving-body issue's 3 mm of jitter.
TEST(AnimateResolve, EveryFrameOfAMovingSceneIsCleanAndSteady) {
  const ResolveScene scene = makeWrinkledTubeScene();
  const std::string dir = tempDir("animate");
  save(dir + "/body.obj", scene.body);
  save(dir + "/garment.obj", scene.garment);
  PointCache body, garment;
  body.points = static_cast<int>(scene.body.V.rows());
  garment.points = static_cast<int>(scene.garment.V.rows());
  for (int f = 0; f < 5; ++f) {
    const Eigen::RowVector3d shift(0.01 * f, 0.002 * f, 0);
    body.samples.push_back(scene.body.V.rowwise() + shift);
    garment.samples.push_back(scene.garment.V.rowwise() + shift);
  }
  std::string err;
  ASSERT_TRUE(writePointCache(dir + "/body.pc2", body, err)) << err;
  ASSERT_TRUE(writePointCache(dir + "/garment.pc2", garment, err)) << err;
  const CliRun run = runCli("animate resolve --body " + dir + "/body.obj --body-cache " + dir + "/body.pc2 --garment " +
                                dir + "/garment.obj --garment-cache " + dir + "/garment.pc2 --out " + dir + "/out.pc2 --check",
                            dir + "/err.txt");
  ASSERT_EQ(run.code, 0) << run.out << run.err;
  EXPECT_TRUE(contains(run.out, "\"frames\": 5")) << run.out;
  EXPECT_TRUE(contains(run.out, "\"frames_with_referee_findings\": 0")) << run.out;
  // Each frame's line says how long the body's tree took: built on frame 0, refitted after.
  EXPECT_TRUE(contains(run.out, "\"ms_body_tree\"")) << run.out;
  EXPECT_TRUE(contains(run.out, "\"body_trees_built\": 1")) << run.out;
  EXPECT_TRUE(contains(run.out, "\"body_trees_refitted\": 4")) << run.out;
  PointCache out;
  ASSERT_TRUE(readPointCache(dir + "/out.pc2", out, err, garment.points)) << err;
  ASSERT_EQ(out.samples.size(), 5u);
  // Frame 0 moved something. With the warm start (the default) the scene moved rigidly, so the last
  // frame's correction, carried over, is clean and no more strained than there: the local
  // relaxation has nothing to do, and the correction moves with the scene (its changes are the
  // cache's float32 rounding).
  const MatrixX3d c0 = out.samples[0] - garment.samples[0];
  EXPECT_GT(c0.rowwise().norm().maxCoeff(), 1e-4);
  auto changes = [&](const PointCache& o) {
    std::vector<double> c;
    for (int f = 1; f < 5; ++f)
      c.push_back(((o.samples[f] - garment.samples[f]) - (o.samples[f - 1] - garment.samples[f - 1]))
                      .rowwise().norm().maxCoeff());
    return c;
  };
  for (double change : changes(out)) EXPECT_LT(change, 1e-6);
  // With --full-relaxation each frame carries on relaxing the last one's correction against its
  // own input: the correction settles, each change within 3 mm and smaller than the one before
  // (measured 1.7, 1.1, 0.7, 0.4 mm).
  // A variant of the run (its options after --check), clean by the referee on every frame; its
  // output cache.
  auto variant = [&](const std::string& name, const std::string& options, CliRun& r) {
    r = runCli("animate resolve --body " + dir + "/body.obj --body-cache " + dir + "/body.pc2 --garment " + dir +
                   "/garment.obj --garment-cache " + dir + "/garment.pc2 --out " + dir + "/" + name + ".pc2 --check " +
                   options,
               dir + "/err_" + name + ".txt");
    EXPECT_EQ(r.code, 0) << r.out << r.err;
    EXPECT_TRUE(contains(r.out, "\"frames_with_referee_findings\": 0")) << r.out;
    PointCache o;
    EXPECT_TRUE(readPointCache(dir + "/" + name + ".pc2", o, err, garment.points)) << err;
    return o;
  };
  CliRun full;
  const PointCache fullOut = variant("full", "--full-relaxation", full);
  ASSERT_EQ(fullOut.samples.size(), 5u);
  double lastChange = 1;
  for (double change : changes(fullOut)) {
    EXPECT_LT(change, 3e-3);
    EXPECT_LT(change, lastChange);
    lastChange = change;
  }
  // The default run starts each frame from the last frame's correction and says so; --cold resolves
  // each frame from its input alone. Both are clean by the referee on every frame, and steady.
  EXPECT_TRUE(contains(run.out, "\"warm_start\": true")) << run.out;
  EXPECT_TRUE(contains(run.out, "\"warm_frames_resolved_cold\": 0")) << run.out;
  CliRun cold;
  const PointCache coldOut = variant("cold", "--cold", cold);
  ASSERT_EQ(coldOut.samples.size(), 5u);
  EXPECT_TRUE(contains(cold.out, "\"warm_start\": false")) << cold.out;
  EXPECT_FALSE(contains(cold.out, "\"warm_start\": true")) << cold.out;
  // Cold, every frame's correction is frame 0's within 3 mm (measured 2.4 mm: the float32 cache's
  // rounding of the moved inputs changes a few of the resolver's decisions).
  const MatrixX3d w0 = coldOut.samples[0] - garment.samples[0];
  for (int f = 1; f < 5; ++f)
    EXPECT_LT(((coldOut.samples[f] - garment.samples[f]) - w0).rowwise().norm().maxCoeff(), 3e-3) << f;
  // Frame 0 has no previous frame: it is resolved cold in both runs, to the same positions.
  EXPECT_LT((coldOut.samples[0] - out.samples[0]).cwiseAbs().maxCoeff(), 1e-6);
  // Temporal coherence is on by default and says what it did; a limit out of range is bad input.
  EXPECT_TRUE(contains(run.out, "\"max_jitter_m\": 0.003")) << run.out;
  EXPECT_TRUE(contains(run.out, "\"vertices_over_max_jitter\"")) << run.out;
  // Then the backward pass, which says what it moved (nothing here: every change is within the
  // limit forward), and --no-backward, which leaves it out: the same frames.
  EXPECT_TRUE(contains(run.out, "\"backward_frames_moved\": 0")) << run.out;
  EXPECT_TRUE(contains(run.out, "\"jitter_max_forward_m\"")) << run.out;
  const CliRun forwardOnly = runCli("animate resolve --body " + dir + "/body.obj --body-cache " + dir +
                                        "/body.pc2 --garment " + dir + "/garment.obj --garment-cache " + dir +
                                        "/garment.pc2 --out " + dir + "/forward.pc2 --no-backward",
                                    dir + "/err4.txt");
  ASSERT_EQ(forwardOnly.code, 0) << forwardOnly.out << forwardOnly.err;
  EXPECT_TRUE(contains(forwardOnly.out, "\"backward_pass\": false")) << forwardOnly.out;
  PointCache forwardOut;
  ASSERT_TRUE(readPointCache(dir + "/forward.pc2", forwardOut, err, garment.points)) << err;
  for (int f = 0; f < 5; ++f) EXPECT_EQ(forwardOut.samples[f], out.samples[f]) << f;
  const CliRun badJitter = runCli("animate resolve --body " + dir + "/body.obj --body-cache " + dir +
                                      "/body.pc2 --garment " + dir + "/garment.obj --garment-cache " + dir +
                                      "/garment.pc2 --out " + dir + "/o.pc2 --max-jitter -1",
                                  dir + "/err3.txt");
  EXPECT_EQ(badJitter.code, 2);
  EXPECT_TRUE(contains(badJitter.err, "--max-jitter")) << badJitter.err;
  // Mismatched caches: exit 2 with the reason.
  const CliRun bad = runCli("animate resolve --body " + dir + "/body.obj --body-cache " + dir + "/garment.pc2 --garment " +
                                dir + "/garment.obj --garment-cache " + dir + "/garment.pc2 --out " + dir + "/o.pc2",
                            dir + "/err2.txt");
  EXPECT_EQ(bad.code, 2);
  EXPECT_TRUE(contains(bad.err, "points, the mesh")) << bad.err;
}

// tryon animate drape on the project's swaying body: the sleeveless shirt draped on frame 0 and worn
// through 4 frames, every frame clean by the referee; frame 0's line gives the cloth's step, within
// dt_safety of the stability limit of the draped cloth (the spectral bound), and every frame takes
// as many steps as that step gives. A --cloth-dt is taken as given, unless it is above the limit.
TEST(AnimateDrape, TheSwayingBodyIsWornCleanAtTheClothsOwnStep) {
  ProceduralAnimationParams ap;
  ap.frames = 5;
  const ProceduralAnimation anim = makeProceduralAnimation(ap);
  const std::string dir = tempDir("animate_drape");
  save(dir + "/body.obj", anim.body);
  PointCache body;
  body.points = static_cast<int>(anim.body.V.rows());
  body.samples = anim.body_frames;
  std::string err;
  ASSERT_TRUE(writePointCache(dir + "/body.pc2", body, err)) << err;
  const std::string base = "animate drape --body " + dir + "/body.obj --body-cache " + dir + "/body.pc2 --pattern " +
                           std::string(VIRTUAL_TRYON_SOURCE_DIR) + "/config/patterns/procedural/sleeveless_shirt.yaml " +
                           "--spacing 0.04 --check --out " + dir + "/worn";
  auto number = [](const std::string& text, const std::string& key) {
    std::smatch m;
    return std::regex_search(text, m, std::regex("\"" + key + "\": ([-0-9.e+]+)")) ? std::stod(m[1]) : -1.0;
  };
  const CliRun run = runCli(base, dir + "/err.txt");
  ASSERT_EQ(run.code, 0) << run.out << run.err;
  EXPECT_TRUE(contains(run.out, "\"frames\": 4")) << run.out;
  EXPECT_TRUE(contains(run.out, "\"frames_with_referee_findings\": 0")) << run.out;
  const double step = number(run.out, "cloth_dt_s"), limit = number(run.out, "cloth_dt_limit_s"),
               bound = number(run.out, "dt_bound_s");
  ASSERT_GT(limit, 0) << run.out;
  EXPECT_LE(step, WornGarmentParams().dt_safety * limit * (1 + 1e-9)) << run.out;
  EXPECT_GT(step, 1.1 * 0.9 * bound) << "the drape's step is 0.9 of the per-node bound";
  EXPECT_TRUE(contains(run.out, "\"steps\": " + std::to_string(static_cast<int>(std::ceil(1.0 / 30 / step - 1e-9)))))
      << run.out;
  PointCache out;
  ASSERT_TRUE(readPointCache(dir + "/worn.pc2", out, err)) << err;
  EXPECT_EQ(out.samples.size(), 5u);
  // Where each frame's resolver time went: the relaxation's setup, rotations and checks, within
  // its total.
  std::istringstream lines(run.out);
  int timed = 0;
  for (std::string line; std::getline(lines, line);) {
    const double total = number(line, "ms_resolve_relaxation");
    if (total < 0) continue;
    ++timed;
    const double setup = number(line, "ms_relaxation_setup"), rotations = number(line, "ms_relaxation_rotations"),
                 checks = number(line, "ms_relaxation_checks");
    EXPECT_GE(std::min({setup, rotations, checks}), 0) << line;
    EXPECT_LE(setup + rotations + checks, total + 1e-6) << line;
    // The frames made ready behind it, at most all but it of the default queue of three.
    const double queued = number(line, "frames_ready_after");
    EXPECT_GE(queued, 0) << line;
    EXPECT_LE(queued, FramesAhead::kDefaultDepth - 1) << line;
  }
  EXPECT_EQ(timed, 4) << run.out;
  const CliRun noQueue = runCli(base + "_none --frames-ahead 0", dir + "/err_none.txt");
  EXPECT_EQ(noQueue.code, 2) << noQueue.out << noQueue.err;
  EXPECT_TRUE(contains(noQueue.err, "--frames-ahead")) << noQueue.err;
  const CliRun given = runCli(base + "_given --cloth-dt 0.0005", dir + "/err_given.txt");
  ASSERT_EQ(given.code, 0) << given.out << given.err;
  EXPECT_NEAR(number(given.out, "cloth_dt_s"), 0.0005, 1e-12) << given.out;
  EXPECT_TRUE(contains(given.out, "\"steps\": 67")) << given.out;
  EXPECT_TRUE(contains(given.out, "\"frames_with_referee_findings\": 0")) << given.out;
  const CliRun unstable = runCli(base + "_unstable --cloth-dt 0.01", dir + "/err_unstable.txt");
  EXPECT_EQ(unstable.code, 2) << unstable.out << unstable.err;
  EXPECT_TRUE(contains(unstable.err, "above its stability limit")) << unstable.err;
}
