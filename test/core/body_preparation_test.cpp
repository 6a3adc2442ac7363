#include "test_helpers.h"
#include "virtual_tryon/core/body/body_check.h"
#include "virtual_tryon/core/body/body_preparation.h"
#include "virtual_tryon/core/geometry/mesh.h"
#include "virtual_tryon/core/scenes/procedural.h"

#include <gtest/gtest.h>

#include <string>
#include <vector>

using namespace virtual_tryon;
using virtual_tryon_test::contains;

namespace {

BodyPreparationParams policy(InsideOutPolicy p) {
  BodyPreparationParams params;
  params.policy = p;
  return params;
}

const char* kFlipped = "body arrived inside out (inward normals) and was flipped";

}  // namespace

TEST(BodyPreparation, OutwardSphereIsAcceptedUnchangedUnderBothPolicies) {
  const TriMesh sphere = makeSphere(0.3, Eigen::Vector3d(0.2, 1.1, -0.4), 3);
  for (InsideOutPolicy p : {InsideOutPolicy::Flip, InsideOutPolicy::Refuse}) {
    const BodyPreparation b = prepareBody(sphere, policy(p));
    ASSERT_TRUE(b.ok) << b.error;
    EXPECT_EQ(b.error, "");
    EXPECT_TRUE(b.warnings.empty());
    EXPECT_FALSE(b.flipped);
    EXPECT_TRUE(b.mesh.F == sphere.F);
    EXPECT_TRUE(b.mesh.V == sphere.V);
    EXPECT_TRUE(b.validation.ok);
    EXPECT_TRUE(b.check.ok);
    EXPECT_TRUE(b.check.closed);
    EXPECT_EQ(b.check.pieces, 1u);
    EXPECT_EQ(b.check.orientation, BodyOrientation::Outward);
    EXPECT_EQ(b.check.summary, checkBody(sphere).summary);
  }
}

TEST(BodyPreparation, FlipTurnsAnInsideOutBodyBackAndSaysSo) {
  const TriMesh sphere = makeSphere(0.3, Eigen::Vector3d(0.2, 1.1, -0.4), 3);
  TriMesh inverted = sphere;
  flipFaces(inverted);
  const BodyPreparation b = prepareBody(inverted, policy(InsideOutPolicy::Flip));
  ASSERT_TRUE(b.ok) << b.error;
  EXPECT_TRUE(b.flipped);
  EXPECT_TRUE(b.check.flipped);
  EXPECT_TRUE(b.mesh.F == sphere.F);
  ASSERT_EQ(b.warnings.size(), 1u);
  EXPECT_EQ(b.warnings[0], kFlipped);
  EXPECT_GT(b.check.signed_volume, 0);
  EXPECT_TRUE(contains(b.check.summary, "inverted: flipped")) << b.check.summary;
  // What orientBody gives for the same mesh.
  TriMesh oriented = inverted;
  const BodyCheck o = orientBody(oriented);
  EXPECT_EQ(b.check.summary, o.summary);
  EXPECT_EQ(b.check.signed_volume, o.signed_volume);
  EXPECT_TRUE(oriented.F == b.mesh.F);
}

TEST(BodyPreparation, RefuseLeavesAnInsideOutBodyAndRefusesIt) {
  TriMesh inverted = makeSphere(0.3, Eigen::Vector3d(0.2, 1.1, -0.4), 3);
  flipFaces(inverted);
  const BodyPreparation b = prepareBody(inverted, policy(InsideOutPolicy::Refuse));
  EXPECT_FALSE(b.ok);
  EXPECT_TRUE(b.check.ok);  // usable, but inside out
  EXPECT_FALSE(b.flipped);
  EXPECT_TRUE(b.mesh.F == inverted.F);
  EXPECT_TRUE(b.warnings.empty());
  EXPECT_TRUE(contains(b.error, "body is inside out: its signed volume is -")) << b.error;
  EXPECT_TRUE(contains(b.error, "(flip every face)")) << b.error;
  EXPECT_EQ(b.check.orientation, BodyOrientation::Inverted);
}

TEST(BodyPreparation, UnusableMeshIsRefusedWithTheValidationMessage) {
  const BodyPreparation empty = prepareBody(TriMesh());
  EXPECT_FALSE(empty.ok);
  EXPECT_FALSE(empty.check.ok);
  EXPECT_FALSE(empty.validation.ok);
  EXPECT_EQ(empty.error, "body has no vertices");
  EXPECT_EQ(empty.check.summary, "unusable: body has no vertices");

  BodyPreparationParams small;
  small.limits.max_vertices = 10;
  const BodyPreparation big = prepareBody(makeSphere(0.3), small);
  EXPECT_FALSE(big.ok);
  EXPECT_TRUE(contains(big.error, "over the limit of 10 vertices")) << big.error;
}

TEST(BodyPreparation, WarningsFollowTheValidationsInOrder) {
  // An open patch (a warning, not fatal) in millimetres, beside a sphere: two pieces.
  TriMesh patch = makePatch(500, 400, 4, 4, Eigen::Vector3d(0, 2000, 0));
  const TriMesh both = concatenate(makeSphere(300), patch);
  const BodyPreparation b = prepareBody(both);
  ASSERT_TRUE(b.ok) << b.error;
  ASSERT_EQ(b.warnings.size(), 3u);
  EXPECT_TRUE(contains(b.warnings[0], "body is ")) << b.warnings[0];
  EXPECT_TRUE(contains(b.warnings[0], "m long")) << b.warnings[0];
  EXPECT_TRUE(contains(b.warnings[1], "body is open (")) << b.warnings[1];
  EXPECT_EQ(b.warnings[2], "body has 2 separate pieces");
  EXPECT_EQ(b.validation.warnings.size(), 1u);
}

TEST(BodyPreparation, AGivenValidationIsUsedAsIs) {
  TriMesh inverted = makeSphere(0.3);
  flipFaces(inverted);
  const BodyPreparation once = prepareBody(inverted);
  const BodyPreparation given = prepareBody(inverted, validate(inverted, "body"), BodyPreparationParams());
  EXPECT_EQ(once.ok, given.ok);
  EXPECT_EQ(once.warnings, given.warnings);
  EXPECT_EQ(once.check.summary, given.check.summary);
  EXPECT_TRUE(once.mesh.F == given.mesh.F);
}

TEST(BodyPreparation, ValidateBodyIsTheRefusingPreparation) {
  TriMesh inverted = makeSphere(0.3);
  flipFaces(inverted);
  const MeshValidation v = validateBody(inverted);
  EXPECT_FALSE(v.ok);
  EXPECT_EQ(v.message, prepareBody(inverted, policy(InsideOutPolicy::Refuse)).error);
  EXPECT_TRUE(v.warnings.empty());

  const TriMesh two = concatenate(makeSphere(0.3), makeSphere(0.2, Eigen::Vector3d(2, 0, 0)));
  const MeshValidation w = validateBody(two);
  EXPECT_TRUE(w.ok);
  EXPECT_EQ(w.warnings, std::vector<std::string>{"body has 2 separate pieces"});
  EXPECT_EQ(w.message, "body has 2 separate pieces");
}
