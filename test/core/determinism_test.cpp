// The same input gives bit-identical output: run after run, and when two runs share the process
// on two threads (as the node's spinner threads do), so that a bag replay is a regression test.
#include "virtual_tryon/core/body/body.h"
#include "virtual_tryon/core/drape/drape.h"
#include "virtual_tryon/core/drape/pattern.h"
#include "virtual_tryon/core/io/pattern_yaml.h"
#include "virtual_tryon/core/resolve/penetration_resolver.h"
#include "virtual_tryon/core/scenes/procedural.h"
#include "virtual_tryon/core/scenes/procedural_body.h"

#include <gtest/gtest.h>

#include <string>
#include <thread>

namespace vt = virtual_tryon;

namespace {

vt::Pattern skirtPattern() {
  vt::Pattern p;
  std::string error;
  EXPECT_TRUE(vt::readPatternYaml(std::string(VIRTUAL_TRYON_SOURCE_DIR) + "/config/patterns/procedural/skirt.yaml",
                                  p, error))
      << error;
  return p;
}

vt::TriMesh resolveOnce(const vt::Body& body, vt::TriMesh garment) {
  const vt::ResolverReport r = vt::resolvePenetrations(body, garment, vt::ResolverParams());
  EXPECT_TRUE(r.converged) << r.reason;
  return garment;
}

vt::TriMesh drapeOnce(const vt::Body& body, const vt::Pattern& pattern) {
  vt::DrapeParams params;
  params.spacing = 0.04;
  params.max_iterations = 600;  // sewing and some draping; the resolver pass runs after
  vt::TriMesh garment;
  const vt::DrapeResult r = vt::drape(body, pattern, params, garment);
  EXPECT_TRUE(r.success) << r.message;
  return garment;
}

void expectBitIdentical(const vt::TriMesh& a, const vt::TriMesh& b) {
  ASSERT_EQ(a.V.rows(), b.V.rows());
  ASSERT_EQ(a.F.rows(), b.F.rows());
  EXPECT_TRUE(a.F == b.F);
  // == on doubles: every coordinate equal to the last bit (no tolerance).
  EXPECT_TRUE(a.V == b.V);
}

}  // namespace

TEST(Determinism, ResolverGivesBitIdenticalResultsAcrossRunsAndThreads) {
  const vt::ResolveScene scene = vt::makeWrinkledTubeScene();
  const vt::Body body(scene.body);
  const vt::TriMesh first = resolveOnce(body, scene.garment);
  expectBitIdentical(first, resolveOnce(body, scene.garment));
  vt::TriMesh a, b;
  std::thread t1([&] { a = resolveOnce(body, scene.garment); });
  std::thread t2([&] { b = resolveOnce(body, scene.garment); });
  t1.join();
  t2.join();
  expectBitIdentical(first, a);
  expectBitIdentical(first, b);
  // A fresh Body (BVH built anew) changes nothing either.
  const vt::Body again(scene.body);
  expectBitIdentical(first, resolveOnce(again, scene.garment));
}

TEST(Determinism, DrapeGivesBitIdenticalResultsAcrossRunsAndThreads) {
  const vt::Body body(vt::makeProceduralBody());
  const vt::Pattern pattern = skirtPattern();
  const vt::TriMesh first = drapeOnce(body, pattern);
  ASSERT_GT(first.numVertices(), 50);
  expectBitIdentical(first, drapeOnce(body, pattern));
  vt::TriMesh a, b;
  std::thread t1([&] { a = drapeOnce(body, pattern); });
  std::thread t2([&] { b = drapeOnce(body, pattern); });
  t1.join();
  t2.join();
  expectBitIdentical(first, a);
  expectBitIdentical(first, b);
}
