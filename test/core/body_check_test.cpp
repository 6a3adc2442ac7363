#include "test_helpers.h"
#include "virtual_tryon/core/body/body_check.h"
#include "virtual_tryon/core/geometry/mesh.h"
#include "virtual_tryon/core/scenes/procedural.h"

#include <gtest/gtest.h>

#include <cmath>
#include <string>

using namespace virtual_tryon;
using virtual_tryon_test::contains;

namespace {

// Splits edge (a, b) of face f at its midpoint m: (a, b, c) becomes (a, m, c), (m, b, c) and the
// zero-area face (a, b, m), which keeps the half-edge a -> b for the neighbour across ab. The mesh
// stays closed and consistently wound, with one more degenerate face.
void addDegenerateFace(TriMesh& mesh, Eigen::Index f) {
  const int a = mesh.F(f, 0), b = mesh.F(f, 1), c = mesh.F(f, 2);
  const int m = static_cast<int>(mesh.V.rows());
  mesh.V.conservativeResize(m + 1, 3);
  mesh.V.row(m) = 0.5 * (mesh.V.row(a) + mesh.V.row(b));
  const Eigen::Index nf = mesh.F.rows();
  mesh.F.conservativeResize(nf + 2, 3);
  mesh.F.row(f) << a, m, c;
  mesh.F.row(nf) << m, b, c;
  mesh.F.row(nf + 1) << a, b, m;
}

}  // namespace

TEST(BodyCheck, SphereIsClosedAndOutward) {
  const TriMesh sphere = makeSphere(0.3, Eigen::Vector3d(0.2, 1.1, -0.4), 3);
  const BodyCheck c = checkBody(sphere);
  ASSERT_TRUE(c.ok) << c.message;
  EXPECT_TRUE(c.closed);
  EXPECT_EQ(c.pieces, 1u);
  EXPECT_EQ(c.boundary_edges, 0u);
  EXPECT_EQ(c.non_manifold_edges, 0u);
  EXPECT_EQ(c.inconsistent_edges, 0u);
  EXPECT_EQ(c.degenerate_faces, 0u);
  EXPECT_EQ(c.orientation, BodyOrientation::Outward);
  EXPECT_EQ(c.inverted_pieces, 0u);
  EXPECT_FALSE(c.flipped);
  EXPECT_NEAR(c.signed_volume, signedVolume(sphere), 1e-12);
  EXPECT_GT(c.signed_volume, 0.9 * 4.0 / 3.0 * M_PI * 0.027);
  EXPECT_TRUE(contains(c.summary, "closed, 1 piece, 0 boundary edges")) << c.summary;
  EXPECT_TRUE(contains(c.summary, "outward")) << c.summary;
}

TEST(BodyCheck, InvertedSphereIsDetectedAndFlippedBack) {
  const TriMesh sphere = makeSphere(0.3, Eigen::Vector3d(0.2, 1.1, -0.4), 3);
  TriMesh inverted = sphere;
  flipFaces(inverted);
  ASSERT_LT(signedVolume(inverted), 0);

  const BodyCheck c = checkBody(inverted);
  ASSERT_TRUE(c.ok) << c.message;
  EXPECT_TRUE(c.closed);
  EXPECT_EQ(c.orientation, BodyOrientation::Inverted);
  EXPECT_EQ(c.inverted_pieces, 1u);
  EXPECT_FALSE(c.flipped);
  EXPECT_NEAR(c.signed_volume, signedVolume(inverted), 1e-12);

  TriMesh fixed = inverted;
  const BodyCheck o = orientBody(fixed);
  ASSERT_TRUE(o.ok) << o.message;
  EXPECT_TRUE(o.flipped);
  EXPECT_EQ(o.flipped_faces, static_cast<std::size_t>(sphere.F.rows()));
  EXPECT_EQ(o.orientation, BodyOrientation::Outward);
  EXPECT_NEAR(o.signed_volume, signedVolume(sphere), 1e-12);
  EXPECT_TRUE(contains(o.summary, "inverted: flipped")) << o.summary;
  // Reversing the winding of each face again gives the original faces exactly.
  EXPECT_EQ(fixed.F, sphere.F);
  EXPECT_EQ(fixed.V, sphere.V);

  // An outward body is left alone.
  TriMesh same = sphere;
  const BodyCheck n = orientBody(same);
  EXPECT_FALSE(n.flipped);
  EXPECT_EQ(n.flipped_faces, 0u);
  EXPECT_EQ(same.F, sphere.F);
}

TEST(BodyCheck, OnlyTheInvertedPieceIsFlipped) {
  const TriMesh a = makeSphere(0.2, Eigen::Vector3d(0, 1, 0), 2);
  TriMesh b = makeCapsule(0.1, 0.4, Eigen::Vector3d(1, 1, 0), 16, 8);
  const double va = signedVolume(a), vb = signedVolume(b);
  flipFaces(b);
  TriMesh both = concatenate(a, b);
  const BodyCheck c = orientBody(both);
  ASSERT_TRUE(c.ok) << c.message;
  EXPECT_EQ(c.pieces, 2u);
  EXPECT_TRUE(c.closed);
  EXPECT_EQ(c.inverted_pieces, 1u);
  EXPECT_TRUE(c.flipped);
  EXPECT_EQ(c.flipped_faces, static_cast<std::size_t>(b.F.rows()));
  EXPECT_NEAR(c.signed_volume, va + vb, 1e-12);
  EXPECT_NEAR(signedVolume(both), va + vb, 1e-12);
  EXPECT_EQ(both.F.topRows(a.F.rows()), a.F);  // the outward piece is untouched
}

TEST(BodyCheck, OpenPatchIsOpenWithItsBoundaryAndUnclear) {
  // nx by nz quads: 2 (nx + nz) boundary edges.
  const TriMesh patch = makePatch(1.0, 0.6, 7, 4, Eigen::Vector3d(0.3, 1.2, 0.1));
  for (bool flip : {false, true}) {
    TriMesh m = patch;
    if (flip) flipFaces(m);
    const BodyCheck c = orientBody(m);
    ASSERT_TRUE(c.ok) << c.message;
    EXPECT_FALSE(c.closed);
    EXPECT_EQ(c.boundary_edges, 22u);
    EXPECT_EQ(c.non_manifold_edges, 0u);
    EXPECT_EQ(c.pieces, 1u);
    // Flat: no volume from its own centre, so no orientation and no flip.
    EXPECT_EQ(c.orientation, BodyOrientation::Unclear);
    EXPECT_EQ(c.unclear_pieces, 1u);
    EXPECT_FALSE(c.flipped);
    EXPECT_NEAR(c.signed_volume, 0.0, 1e-12);
    EXPECT_TRUE(contains(c.summary, "open, 1 piece, 22 boundary edges")) << c.summary;
    EXPECT_TRUE(contains(c.summary, "a hint only")) << c.summary;
    EXPECT_TRUE(contains(c.summary, "orientation unclear")) << c.summary;
  }
}

TEST(BodyCheck, OpenTubeOrientationIsAHintAndAnInvertedOneIsFlipped) {
  // A tube (no caps): 2 x 24 boundary edges; from its centre it encloses most of the cylinder.
  const TriMesh tube = makeCylinder(0.15, 0.6, Eigen::Vector3d(0.5, 0.9, 0), 24, 6, false);
  const BodyCheck c = checkBody(tube);
  ASSERT_TRUE(c.ok) << c.message;
  EXPECT_FALSE(c.closed);
  EXPECT_EQ(c.boundary_edges, 48u);
  EXPECT_EQ(c.orientation, BodyOrientation::Outward);
  EXPECT_GT(c.signed_volume, 0.0);

  TriMesh inverted = tube;
  flipFaces(inverted);
  const BodyCheck o = orientBody(inverted);
  EXPECT_EQ(o.inverted_pieces, 1u);
  EXPECT_TRUE(o.flipped);
  EXPECT_EQ(inverted.F, tube.F);
  EXPECT_NEAR(o.signed_volume, c.signed_volume, 1e-12);

  // A tube with only some of its faces reversed has no clear sign: left alone.
  TriMesh mixed = tube;
  for (Eigen::Index f = 0; f < mixed.F.rows(); f += 2) std::swap(mixed.F(f, 1), mixed.F(f, 2));
  const BodyCheck x = orientBody(mixed);
  EXPECT_GT(x.inconsistent_edges, 0u);
  EXPECT_FALSE(x.flipped);
  EXPECT_EQ(x.orientation, BodyOrientation::Unclear);
}

TEST(BodyCheck, DegenerateFacesAreCounted) {
  TriMesh sphere = makeSphere(0.3, Eigen::Vector3d(0, 1, 0), 3);
  const double volume = signedVolume(sphere);
  for (int i = 0; i < 12; ++i) addDegenerateFace(sphere, 100 * i);
  const BodyCheck c = checkBody(sphere);
  ASSERT_TRUE(c.ok) << c.message;
  EXPECT_EQ(c.degenerate_faces, 12u);
  EXPECT_TRUE(c.closed);
  EXPECT_EQ(c.boundary_edges, 0u);
  EXPECT_EQ(c.inconsistent_edges, 0u);
  EXPECT_EQ(c.orientation, BodyOrientation::Outward);
  EXPECT_NEAR(c.signed_volume, volume, 1e-12);
  EXPECT_TRUE(contains(c.summary, "12 degenerate faces")) << c.summary;
}

TEST(BodyCheck, NonManifoldEdgeMakesItNotClosed) {
  // Three faces on one edge (a fin glued to a sphere's edge).
  TriMesh m = makeSphere(0.3, Eigen::Vector3d(0, 1, 0), 2);
  const int a = m.F(0, 0), b = m.F(0, 1);
  const int t = static_cast<int>(m.V.rows());
  m.V.conservativeResize(t + 1, 3);
  m.V.row(t) = m.V.row(a) * 1.5;
  m.F.conservativeResize(m.F.rows() + 1, 3);
  m.F.row(m.F.rows() - 1) << a, b, t;
  const BodyCheck c = checkBody(m);
  ASSERT_TRUE(c.ok) << c.message;
  EXPECT_FALSE(c.closed);
  EXPECT_EQ(c.non_manifold_edges, 1u);
  EXPECT_EQ(c.boundary_edges, 2u);
  // Not exact any more, but the sign is still clear.
  EXPECT_EQ(c.orientation, BodyOrientation::Outward);
}

TEST(BodyCheck, UnusableMeshesAreReported) {
  const BodyCheck empty = checkBody(TriMesh());
  EXPECT_FALSE(empty.ok);
  EXPECT_FALSE(empty.message.empty());
  EXPECT_TRUE(contains(empty.summary, "unusable")) << empty.summary;

  TriMesh bad = makeSphere(0.3);
  bad.F(3, 1) = 100000;
  TriMesh copy = bad;
  const BodyCheck c = orientBody(copy);
  EXPECT_FALSE(c.ok);
  EXPECT_TRUE(contains(c.message, "out of range")) << c.message;
  EXPECT_EQ(copy.F, bad.F);

  TriMesh nan = makeSphere(0.3);
  nan.V(0, 0) = NAN;
  EXPECT_FALSE(checkBody(nan).ok);

  BodyCheckParams p;
  p.open_flip_ratio = 0;
  const BodyCheck r = checkBody(makeSphere(0.3), p);
  EXPECT_FALSE(r.ok);
  EXPECT_TRUE(contains(r.message, "open_flip_ratio")) << r.message;
}

TEST(BodyCheck, TheCallersSizeLimitsApply) {
  // The node passes its ~max_vertices / ~max_faces: a body the defaults allow is refused by
  // smaller limits.
  TriMesh m = makeSphere(0.3, Eigen::Vector3d(0, 1, 0), 2);
  BodyCheckParams p;
  EXPECT_TRUE(orientBody(m, p).ok);
  p.limits.max_vertices = static_cast<std::size_t>(m.V.rows()) - 1;
  const BodyCheck small = orientBody(m, p);
  EXPECT_FALSE(small.ok);
  EXPECT_NE(small.message.find("limit"), std::string::npos) << small.message;
}
