#include "test_helpers.h"
#include "virtual_tryon/core/body/body_check.h"
#include "virtual_tryon/core/geometry/mesh.h"
#include "virtual_tryon/core/scenes/procedural.h"
#include "virtual_tryon/core/scenes/procedural_body.h"
#include "virtual_tryon/core/body/scan_meshing.h"
#include "virtual_tryon/core/scenes/synthetic_scan.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

using namespace virtual_tryon;
using virtual_tryon_test::contains;

namespace {

const double kPi = 3.14159265358979323846;

// The analytic sphere of the tests and a fine icosphere of it (20480 faces: its chords stay within
// 0.03 mm of the sphere).
const double kRadius = 0.3;
const Eigen::Vector3d kCentre(0.1, 1.0, -0.2);
const TriMesh& fineSphere() {
  static const TriMesh m = makeSphere(kRadius, kCentre, 5);
  return m;
}

SyntheticScan sphereScan(std::size_t n = 20000, double sigma = 0.001, std::uint64_t seed = 7) {
  SyntheticScanParams p;
  p.points = n;
  p.noise_sigma = sigma;
  p.seed = seed;
  return syntheticScan(fineSphere(), p);
}

void expectClosedOutward(const ScanMeshingResult& r) {
  ASSERT_TRUE(r.success) << r.message;
  EXPECT_TRUE(r.closed);
  EXPECT_EQ(r.boundary_edges, 0u);
  EXPECT_EQ(r.non_manifold_edges, 0u);
  EXPECT_GT(r.signed_volume, 0.0);
  const EdgeTopology t = edgeTopology(r.mesh);  // independently of the result's own counts
  EXPECT_TRUE(t.closed());
  EXPECT_NEAR(signedVolume(r.mesh), r.signed_volume, 1e-9);
  EXPECT_EQ(r.vertices, static_cast<std::size_t>(r.mesh.V.rows()));
  EXPECT_EQ(r.faces, static_cast<std::size_t>(r.mesh.F.rows()));
  EXPECT_TRUE(validate(r.mesh).ok);
  EXPECT_EQ(validate(r.mesh).unused_vertices, 0u);
}

// max | |v - c| - r | over the vertices.
double maxRadialError(const TriMesh& m) {
  double e = 0;
  for (Eigen::Index i = 0; i < m.V.rows(); ++i)
    e = std::max(e, std::abs((m.V.row(i).transpose() - kCentre).norm() - kRadius));
  return e;
}

}  // namespace

// ---------------------------------------------------------------------------------------------
// The synthetic scan.

TEST(ScanMeshingSyntheticScan, DeterministicUniformAndNoisy) {
  const SyntheticScan a = sphereScan(20000, 0.001, 42);
  const SyntheticScan b = sphereScan(20000, 0.001, 42);
  const SyntheticScan c = sphereScan(20000, 0.001, 43);
  ASSERT_TRUE(a.success) << a.message;
  ASSERT_EQ(a.points.rows(), 20000);
  EXPECT_EQ(a.points, b.points);  // bit for bit
  EXPECT_EQ(a.face, b.face);
  EXPECT_NE(a.points, c.points);
  EXPECT_NEAR(a.surface_area, 4 * kPi * kRadius * kRadius, 0.002 * 4 * kPi * kRadius * kRadius);

  // Radial offsets: mean ~0, standard deviation ~sigma (the normal component of isotropic noise).
  double sum = 0, sum2 = 0;
  for (Eigen::Index i = 0; i < a.points.rows(); ++i) {
    const double d = (a.points.row(i).transpose() - kCentre).norm() - kRadius;
    sum += d;
    sum2 += d * d;
  }
  const double mean = sum / 20000, sd = std::sqrt(sum2 / 20000 - mean * mean);
  EXPECT_NEAR(mean, 0.0, 1e-4);
  EXPECT_NEAR(sd, 0.001, 5e-5);

  // Uniform by area: each octant of the sphere gets 1/8 of the points (binomial sd ~ 0.2%).
  int octant[8] = {0};
  for (Eigen::Index i = 0; i < a.points.rows(); ++i) {
    const Eigen::Vector3d d = a.points.row(i).transpose() - kCentre;
    ++octant[(d.x() > 0) + 2 * (d.y() > 0) + 4 * (d.z() > 0)];
  }
  for (int o = 0; o < 8; ++o) EXPECT_NEAR(octant[o] / 20000.0, 0.125, 0.012) << "octant " << o;

  // Without noise every point is on the mesh (within the icosphere's chord error of the sphere).
  const SyntheticScan exact = sphereScan(2000, 0.0, 1);
  ASSERT_TRUE(exact.success);
  for (Eigen::Index i = 0; i < exact.points.rows(); ++i)
    ASSERT_NEAR((exact.points.row(i).transpose() - kCentre).norm(), kRadius, 1e-4);
}

TEST(ScanMeshingSyntheticScan, FirstPointsArePinned) {
  // Pins the generator: std::mt19937_64, the top 53 bits per uniform and the square-root barycentric
  // mapping are exact, so noise-free points are the same on every platform (a change here changes
  // every scan). With noise, std::log / std::cos / std::sin may differ in the last bit between
  // C libraries, hence the tolerance there.
  TriMesh tri;
  tri.V.resize(3, 3);
  tri.V << 0, 0, 0, 1, 0, 0, 0, 1, 0;
  tri.F.resize(1, 3);
  tri.F << 0, 1, 2;
  SyntheticScanParams p;
  p.points = 2;
  p.noise_sigma = 0;
  p.seed = 5;
  const SyntheticScan s = syntheticScan(tri, p);
  ASSERT_TRUE(s.success) << s.message;
  EXPECT_DOUBLE_EQ(s.points(0, 0), 0.15199872235036885);
  EXPECT_DOUBLE_EQ(s.points(0, 1), 0.044201712938850161);
  EXPECT_DOUBLE_EQ(s.points(1, 0), 0.27164928027064933);
  EXPECT_DOUBLE_EQ(s.points(1, 1), 0.028961580503601689);
  EXPECT_EQ(s.points(0, 2), 0.0);
  EXPECT_EQ(s.points(1, 2), 0.0);

  p.noise_sigma = 0.01;
  const SyntheticScan n = syntheticScan(tri, p);
  ASSERT_TRUE(n.success) << n.message;
  EXPECT_NEAR(n.points(0, 0), 0.16465520646912196, 1e-12);
  EXPECT_NEAR(n.points(0, 1), 0.052274748670591682, 1e-12);
  EXPECT_NEAR(n.points(0, 2), 0.0030848885173929115, 1e-12);
  EXPECT_NEAR(n.points(1, 0), 0.69869347198623488, 1e-12);
  EXPECT_NEAR(n.points(1, 1), 0.19269582200433114, 1e-12);
  EXPECT_NEAR(n.points(1, 2), -0.0014221239969020541, 1e-12);
}

TEST(ScanMeshingSyntheticScan, BadInput) {
  SyntheticScanParams p;
  EXPECT_FALSE(syntheticScan(TriMesh(), p).success);
  p.points = 0;
  const SyntheticScan z = syntheticScan(fineSphere(), p);
  EXPECT_FALSE(z.success);
  EXPECT_TRUE(contains(z.message, "points")) << z.message;
  p.points = 10;
  p.noise_sigma = -1;
  const SyntheticScan n = syntheticScan(fineSphere(), p);
  EXPECT_FALSE(n.success);
  EXPECT_TRUE(contains(n.message, "noise_sigma")) << n.message;
}

// ---------------------------------------------------------------------------------------------
// Meshing.

TEST(ScanMeshing, SphereScanReconstructsClosedOutwardAndAccurate) {
  const SyntheticScan scan = sphereScan();
  ASSERT_TRUE(scan.success) << scan.message;
  // Depth 7: 5.2 mm cells on this sphere's 0.66 m box. Measured over seeds 1-3 (1 mm noise): max
  // radial error 1.2-1.4 mm at depth 7 (the default), 1.3-1.5 mm at depth 8 (30% slower), 1.0-1.2 mm
  // at depth 6; volume within 0.07% at all three. No downsampling: every sample is used.
  ScanMeshingParams p;
  p.depth = 7;
  p.voxel_size = 0;
  const ScanMeshingResult r = meshScan(scan.points, MatrixX3d(), p);
  expectClosedOutward(r);
  EXPECT_EQ(r.input_points, 20000u);
  EXPECT_EQ(r.points_after_downsampling, 20000u);
  EXPECT_EQ(r.non_finite_points, 0u);
  EXPECT_TRUE(r.normals_estimated);
  EXPECT_TRUE(r.normals_reoriented);
  EXPECT_EQ(r.graph_components, 1u);
  EXPECT_GT(r.seconds_reconstruct, 0.0);
  EXPECT_GE(r.seconds_total, r.seconds_normals + r.seconds_orient + r.seconds_reconstruct);

  const double err = maxRadialError(r.mesh);
  const double volume = 4.0 / 3.0 * kPi * kRadius * kRadius * kRadius;
  RecordProperty("max_radial_error_mm", std::to_string(1e3 * err));
  RecordProperty("volume_error_percent", std::to_string(100 * (r.signed_volume - volume) / volume));
  EXPECT_LT(err, 0.0025) << "max radial error " << err << " m";
  EXPECT_NEAR(r.signed_volume, volume, 0.005 * volume);
  std::vector<int> label;
  EXPECT_EQ(connectedComponents(r.mesh, label), 1);
}

TEST(ScanMeshing, GivenNormalsAreUsedOrReoriented) {
  const SyntheticScan scan = sphereScan(8000, 0.0005, 3);
  ASSERT_TRUE(scan.success);
  MatrixX3d outward(scan.points.rows(), 3);
  for (Eigen::Index i = 0; i < scan.points.rows(); ++i)
    outward.row(i) = (scan.points.row(i).transpose() - kCentre).normalized().transpose() * 2.0;  // any length

  ScanMeshingParams p;
  p.depth = 6;  // the logic, not the accuracy, is tested here
  const ScanMeshingResult given = meshScan(scan.points, outward, p);
  expectClosedOutward(given);
  EXPECT_FALSE(given.normals_estimated);
  EXPECT_FALSE(given.normals_reoriented);
  EXPECT_EQ(given.normals_flipped, 0u);
  EXPECT_EQ(given.normal_disagreement, 0.0);
  EXPECT_FALSE(given.flipped);

  // Consistently inward: used as they are, the surface comes out inverted and is flipped.
  const ScanMeshingResult inward = meshScan(scan.points, MatrixX3d(-outward), p);
  expectClosedOutward(inward);
  EXPECT_FALSE(inward.normals_reoriented);
  EXPECT_TRUE(inward.flipped);
  EXPECT_NEAR(inward.signed_volume, given.signed_volume, 0.01 * given.signed_volume);

  // Random signs: inconsistent, so re-oriented by propagation.
  MatrixX3d mixed = outward;
  for (Eigen::Index i = 0; i < mixed.rows(); i += 3) mixed.row(i) *= -1;
  const ScanMeshingResult re = meshScan(scan.points, mixed, p);
  expectClosedOutward(re);
  EXPECT_TRUE(re.normals_reoriented);
  EXPECT_GT(re.normal_disagreement, 0.2);
  EXPECT_NEAR(re.signed_volume, given.signed_volume, 0.01 * given.signed_volume);
}

TEST(ScanMeshing, SeveralPiecesAreOrientedSeparately) {
  // Two spheres 1 m apart: two components of the kNN graph, each seeded on its own.
  SyntheticScanParams p;
  p.points = 12000;
  p.noise_sigma = 0.0005;
  const TriMesh two = concatenate(makeSphere(0.2, Eigen::Vector3d(0, 1, 0), 4),
                                  makeSphere(0.15, Eigen::Vector3d(1, 1, 0), 4));
  const SyntheticScan scan = syntheticScan(two, p);
  ASSERT_TRUE(scan.success);
  ScanMeshingParams mp;
  mp.depth = 7;
  const ScanMeshingResult r = meshScan(scan.points, MatrixX3d(), mp);
  expectClosedOutward(r);
  EXPECT_EQ(r.graph_components, 2u);
  EXPECT_EQ(r.check.pieces, 2u);
  EXPECT_EQ(r.check.inverted_pieces, 0u);
  const double volume = 4.0 / 3.0 * kPi * (0.2 * 0.2 * 0.2 + 0.15 * 0.15 * 0.15);
  EXPECT_NEAR(r.signed_volume, volume, 0.03 * volume);
}

TEST(ScanMeshing, ProceduralBodyScanReconstructsClosedAndOutward) {
  const TriMesh body = makeProceduralBody();
  SyntheticScanParams sp;
  sp.points = 60000;
  sp.noise_sigma = 0.001;
  const SyntheticScan scan = syntheticScan(body, sp);
  ASSERT_TRUE(scan.success) << scan.message;
  ScanMeshingParams p;
  p.voxel_size = 0.01;
  p.depth = 7;
  const ScanMeshingResult r = meshScan(scan.points, MatrixX3d(), p);
  expectClosedOutward(r);
  EXPECT_LT(r.points_after_downsampling, r.input_points);
  EXPECT_GT(r.seconds_downsample, 0.0);
  const double volume = signedVolume(body);
  RecordProperty("volume_error_percent", std::to_string(100 * (r.signed_volume - volume) / volume));
  EXPECT_NEAR(r.signed_volume, volume, 0.1 * volume);
  std::vector<int> label;
  EXPECT_EQ(connectedComponents(r.mesh, label), 1);
  Eigen::Vector3d lo, hi, blo, bhi;
  boundingBox(r.mesh, lo, hi);
  boundingBox(body, blo, bhi);
  EXPECT_NEAR(hi.y() - lo.y(), bhi.y() - blo.y(), 0.02);
}

TEST(ScanMeshing, BadInputIsRefusedWithAMessage) {
  const ScanMeshingResult empty = meshScan(MatrixX3d(), MatrixX3d());
  EXPECT_FALSE(empty.success);
  EXPECT_TRUE(contains(empty.message, "no points")) << empty.message;

  MatrixX3d nan = MatrixX3d::Constant(500, 3, std::numeric_limits<double>::quiet_NaN());
  const ScanMeshingResult allNan = meshScan(nan, MatrixX3d());
  EXPECT_FALSE(allNan.success);
  EXPECT_EQ(allNan.non_finite_points, 500u);
  EXPECT_TRUE(contains(allNan.message, "too few valid points: 0 of 500")) << allNan.message;

  const SyntheticScan scan = sphereScan(50, 0.001, 9);
  const ScanMeshingResult few = meshScan(scan.points, MatrixX3d());
  EXPECT_FALSE(few.success);
  EXPECT_TRUE(contains(few.message, "too few valid points: 50 of 50")) << few.message;
  EXPECT_TRUE(contains(few.message, "min_points = 100")) << few.message;

  const ScanMeshingResult wrongNormals = meshScan(sphereScan(200).points, MatrixX3d::Ones(3, 3));
  EXPECT_FALSE(wrongNormals.success);
  EXPECT_TRUE(contains(wrongNormals.message, "normals")) << wrongNormals.message;

  // Parameters: the message names the parameter.
  const MatrixX3d pts = sphereScan(500).points;
  auto refused = [&](ScanMeshingParams p, const std::string& name) {
    const ScanMeshingResult r = meshScan(pts, MatrixX3d(), p);
    EXPECT_FALSE(r.success) << name;
    EXPECT_TRUE(contains(r.message, name)) << r.message;
  };
  ScanMeshingParams p;
  p.voxel_size = -0.01;
  refused(p, "voxel_size");
  p = ScanMeshingParams();
  p.voxel_size = 1e-5;  // more voxels than PCL can index
  refused(p, "voxel_size");
  p = ScanMeshingParams();
  p.depth = 3;
  refused(p, "depth");
  p.depth = -1;
  refused(p, "depth");
  p.depth = 13;
  refused(p, "depth");
  p = ScanMeshingParams();
  p.normal_neighbours = 2;
  refused(p, "normal_neighbours");
  p = ScanMeshingParams();
  p.samples_per_node = 0.5;
  refused(p, "samples_per_node");
  p = ScanMeshingParams();
  p.min_piece_fraction = 2;
  refused(p, "min_piece_fraction");
  p = ScanMeshingParams();
  p.threads = -1;
  refused(p, "threads");
  p = ScanMeshingParams();
  p.max_auto_depth = 3;
  refused(p, "max_auto_depth");
  p = ScanMeshingParams();
  p.max_hole_edges = -1;
  refused(p, "max_hole_edges");
  EXPECT_EQ(validateScanMeshingParams(ScanMeshingParams()), "");
}

TEST(ScanMeshing, NonFinitePointsAreDroppedAndCounted) {
  SyntheticScan scan = sphereScan(6000, 0.0005, 11);
  ASSERT_TRUE(scan.success);
  for (Eigen::Index i = 0; i < 6000; i += 100) scan.points(i, i % 3) = std::numeric_limits<double>::quiet_NaN();
  scan.points(1, 2) = std::numeric_limits<double>::infinity();
  ScanMeshingParams p;
  p.depth = 6;
  p.voxel_size = 0;  // every finite point is used
  const ScanMeshingResult r = meshScan(scan.points, MatrixX3d(), p);
  expectClosedOutward(r);
  EXPECT_EQ(r.non_finite_points, 61u);
  EXPECT_EQ(r.points_after_downsampling, 6000u - 61u);
}

TEST(ScanMeshing, CavityWallsAreRemoved) {
  // A hollow ball (outer radius 0.3 m, a 0.15 m cavity wound inward) scanned with its true normals:
  // Poisson gives the outer surface and the cavity's wall, wound oppositely.
  const TriMesh outer = makeSphere(0.3, kCentre, 4);
  TriMesh inner = makeSphere(0.15, kCentre, 4);
  flipFaces(inner);
  const TriMesh shell = concatenate(outer, inner);
  SyntheticScanParams sp;
  sp.points = 12000;
  sp.noise_sigma = 0.0005;
  const SyntheticScan scan = syntheticScan(shell, sp);
  ASSERT_TRUE(scan.success);
  const MatrixX3d faceN = faceNormals(shell);
  MatrixX3d normals(scan.points.rows(), 3);
  for (Eigen::Index i = 0; i < normals.rows(); ++i) normals.row(i) = faceN.row(scan.face[static_cast<std::size_t>(i)]);

  ScanMeshingParams p;
  p.depth = 7;
  const ScanMeshingResult r = meshScan(scan.points, normals, p);
  expectClosedOutward(r);
  EXPECT_FALSE(r.normals_reoriented);
  EXPECT_EQ(r.cavities_removed, 1u);
  EXPECT_EQ(r.check.pieces, 1u);
  const double ball = 4.0 / 3.0 * kPi * 0.027;
  EXPECT_NEAR(r.signed_volume, ball, 0.01 * ball);

  p.remove_cavities = false;  // kept: the wall is an inverted piece for the body check, and flipped
  const ScanMeshingResult kept = meshScan(scan.points, normals, p);
  ASSERT_TRUE(kept.success) << kept.message;
  EXPECT_EQ(kept.cavities_removed, 0u);
  EXPECT_EQ(kept.check.pieces, 2u);
  EXPECT_EQ(kept.check.inverted_pieces, 1u);
}

TEST(ScanMeshing, SmallHolesAreClosed) {
  const TriMesh sphere = makeSphere(0.3, kCentre, 3);
  const double volume = signedVolume(sphere);

  // One face removed: a 3-edge hole, closed by one triangle.
  TriMesh one = sphere;
  one.F.row(5) = one.F.row(one.F.rows() - 1);
  one.F.conservativeResize(one.F.rows() - 1, 3);
  ASSERT_EQ(edgeTopology(one).boundary_edges, 3u);
  std::size_t added = 0;
  EXPECT_EQ(closeSmallHoles(one, 64, &added), 1u);
  EXPECT_EQ(added, 1u);
  EXPECT_TRUE(edgeTopology(one).closed());
  EXPECT_NEAR(signedVolume(one), volume, 1e-12);
  EXPECT_EQ(checkBody(one).inconsistent_edges, 0u);

  // The faces round vertex 0 removed (a 5-edge hole at an icosahedron corner), and, far from it,
  // the faces round another vertex: two holes, closed by fans; the limit leaves longer loops open.
  TriMesh two = sphere;
  const int other = static_cast<int>(two.V.rows()) - 1;
  MatrixX3i F(two.F.rows(), 3);
  Eigen::Index nf = 0;
  for (Eigen::Index f = 0; f < two.F.rows(); ++f)
    if ((two.F.row(f).array() != 0).all() && (two.F.row(f).array() != other).all()) F.row(nf++) = two.F.row(f);
  F.conservativeResize(nf, 3);
  two.F = F;
  const std::size_t boundary = edgeTopology(two).boundary_edges;
  ASSERT_GE(boundary, 10u);
  TriMesh limited = two;
  EXPECT_EQ(closeSmallHoles(limited, 4), 0u);
  EXPECT_EQ(edgeTopology(limited).boundary_edges, boundary);
  const Eigen::Index v0 = two.V.rows();
  EXPECT_EQ(closeSmallHoles(two, 64, &added), 2u);
  EXPECT_EQ(added, boundary);  // one fan triangle per boundary edge
  EXPECT_EQ(two.V.rows(), v0 + 2);  // the fan centres
  EXPECT_TRUE(edgeTopology(two).closed());
  const BodyCheck c = checkBody(two);
  EXPECT_EQ(c.inconsistent_edges, 0u);
  EXPECT_EQ(c.orientation, BodyOrientation::Outward);
  EXPECT_NEAR(signedVolume(two), volume, 0.01 * volume);

  // Nothing to do on a closed mesh.
  TriMesh closed = sphere;
  EXPECT_EQ(closeSmallHoles(closed, 64), 0u);
  EXPECT_EQ(closed.F, sphere.F);
}
