// The scan's error bar (scan_error.h), the depth chosen from the scan, and the check against the
// truth: a known body is scanned, meshed through the scan path, a garment is fitted to the mesh with
// the scan's error as the body's uncertainty, and the independent referee counts against the TRUE
// body.
#include "test_helpers.h"
#include "virtual_tryon/core/body/body.h"
#include "virtual_tryon/core/body/scan_error.h"
#include "virtual_tryon/core/body/scan_meshing.h"
#include "virtual_tryon/core/geometry/mesh.h"
#include "virtual_tryon/core/resolve/penetration_resolver.h"
#include "virtual_tryon/core/scenes/demo_scene.h"
#include "virtual_tryon/core/scenes/procedural.h"
#include "virtual_tryon/core/scenes/procedural_body.h"
#include "virtual_tryon/core/scenes/synthetic_scan.h"
#include "virtual_tryon/testing/reference_bvh.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

using namespace virtual_tryon;

namespace {

SyntheticScan scanOf(const TriMesh& mesh, std::size_t n, double sigma, std::uint64_t seed = 3) {
  SyntheticScanParams p;
  p.points = n;
  p.noise_sigma = sigma;
  p.seed = seed;
  return syntheticScan(mesh, p);
}

const TriMesh& proceduralBody() {
  static const TriMesh body = makeProceduralBody();
  return body;
}

}  // namespace

TEST(ScanNoise, EstimatedWithinFifteenPercentOnABody) {
  // Measured on this body (50k points): 0.5 -> 0.55, 1 -> 1.05, 3 -> 3.1 mm; on body_hm08 the same
  // within 8% from 50k to 200k points (scan_benchmark --grid).
  for (double sigma : {0.0005, 0.001, 0.003}) {
    const SyntheticScan scan = scanOf(proceduralBody(), 50000, sigma);
    ASSERT_TRUE(scan.success);
    const ScanNoiseEstimate e = estimateScanNoise(scan.points);
    RecordProperty("sigma_" + std::to_string(static_cast<int>(1e4 * sigma)) + "_estimated_mm",
                   std::to_string(1e3 * e.sigma));
    EXPECT_NEAR(e.sigma, sigma, 0.15 * sigma) << "sigma " << sigma;
    EXPECT_GT(e.samples, 3000u);
  }
}

TEST(ScanNoise, CurvatureIsNotTakenForNoise) {
  // Noise-free points on a sphere of radius 5 cm (an arm): a plane fit would see its sagitta,
  // about 0.5 mm over these neighbourhoods; the quadric sees almost nothing.
  const SyntheticScan scan = scanOf(makeSphere(0.05, Eigen::Vector3d::Zero(), 5), 20000, 0.0);
  ASSERT_TRUE(scan.success);
  EXPECT_LT(estimateScanNoise(scan.points).sigma, 1e-4);
  // Too few points: no estimate.
  EXPECT_EQ(estimateScanNoise(scan.points.topRows(10)).sigma, 0.0);
  EXPECT_EQ(estimateScanNoise(MatrixX3d()).samples, 0u);
}

TEST(ScanError, DistancesOfPointsToTheMeshAreMeasured) {
  const TriMesh sphere = makeSphere(0.2, Eigen::Vector3d::Zero(), 4);
  const SyntheticScan onSurface = scanOf(sphere, 5000, 0.0);
  const ScanError zero = measureScanError(onSurface.points, sphere);
  EXPECT_EQ(zero.points, 5000u);
  EXPECT_LT(zero.max, 1e-9);
  EXPECT_EQ(zero.share_over_2mm, 0.0);

  // Every point moved out along its face's normal by 1 mm, and 3 mm for the second half.
  const MatrixX3d n = faceNormals(sphere);
  MatrixX3d pts = onSurface.points;
  for (Eigen::Index i = 0; i < pts.rows(); ++i)
    pts.row(i) += (i < 2500 ? 0.001 : 0.003) * n.row(onSurface.face[static_cast<std::size_t>(i)]);
  const ScanError e = measureScanError(pts, sphere);
  EXPECT_NEAR(e.median, 0.002, 0.0011);  // the ranks 2500 / 2501 sit between the two groups
  EXPECT_NEAR(e.p95, 0.003, 1e-6);
  EXPECT_NEAR(e.max, 0.003, 1e-6);
  EXPECT_NEAR(e.share_over_2mm, 0.5, 1e-9);

  // A stride: at most 1000 points measured; non-finite rows skipped.
  pts(7, 1) = std::numeric_limits<double>::quiet_NaN();
  const ScanError some = measureScanError(pts, sphere, 1000);
  EXPECT_LE(some.points, 1000u);
  EXPECT_GT(some.points, 800u);
  EXPECT_TRUE(std::isfinite(some.max));
  EXPECT_EQ(measureScanError(pts, TriMesh()).points, 0u);
}

TEST(ScanDepth, ChosenFromExtentSpacingAndNoise) {
  // 1.1 * 1.75 m / 2^d <= max(1.5 * spacing, 2 * sigma):
  EXPECT_EQ(chooseScanDepth(1.75, 0.0035, 0.001, 12), 9);  // cell <= 5.25 mm: 3.8 mm
  EXPECT_EQ(chooseScanDepth(1.75, 0.0035, 0.001, 8), 8);   // held to the cap
  EXPECT_EQ(chooseScanDepth(1.75, 0.007, 0.001, 12), 8);   // cell <= 10.5 mm: 7.5 mm
  EXPECT_EQ(chooseScanDepth(1.75, 0.0035, 0.006, 12), 8);  // noisy: cell <= 12 mm
  EXPECT_EQ(chooseScanDepth(1.75, 0.5, 0.0, 12), 5);       // sparse: never coarser than 5
  EXPECT_EQ(chooseScanDepth(0.0, 0.0035, 0.001, 8), 8);    // degenerate: the cap
  EXPECT_EQ(chooseScanDepth(1.75, 0.0, 0.0, 8), 8);
}

TEST(ScanMeshing, ReportsTheDepthItChoseAndTheScansError) {
  const SyntheticScan scan = scanOf(proceduralBody(), 60000, 0.001);
  ASSERT_TRUE(scan.success);
  const ScanMeshingResult r = meshScan(scan.points, MatrixX3d());
  ASSERT_TRUE(r.success) << r.message;
  EXPECT_GE(r.depth, 7);
  EXPECT_LE(r.depth, ScanMeshingParams().max_auto_depth);
  EXPECT_GT(r.point_spacing, 0.001);
  EXPECT_NEAR(r.noise.sigma, 0.001, 0.00015);
  EXPECT_EQ(r.error.points, 30000u);  // held to the default cap of 50000: every second point
  EXPECT_LE(r.error.median, r.error.p95);
  EXPECT_LE(r.error.p95, r.error.max);
  RecordProperty("depth", r.depth);
  RecordProperty("error_p95_mm", std::to_string(1e3 * r.error.p95));
  RecordProperty("error_ratio", std::to_string(r.error_ratio));
  // The mesh follows the points: the 95th percentile within 1.5x what the noise alone gives.
  EXPECT_GT(r.error_ratio, 0.7);
  EXPECT_LE(r.error_ratio, 1.5);
  EXPECT_NEAR(r.error_ratio, r.error.p95 / (1.96 * r.noise.sigma), 0.01);

  ScanMeshingParams fixed;
  fixed.depth = 6;
  const ScanMeshingResult coarse = meshScan(scan.points, MatrixX3d(), fixed);
  ASSERT_TRUE(coarse.success) << coarse.message;
  EXPECT_EQ(coarse.depth, 6);
  EXPECT_GT(coarse.error.p95, r.error.p95);  // coarser cells smooth the limbs away
}

TEST(ScanTruth, AGarmentFittedToTheScansMeshClearsTheTrueBody) {
  // The procedural body (the truth), scanned (60k points, 1 mm noise, no normals) and meshed
  // through the scan path; a tight waist tube, 1.5 mm off the true body where its folds do not dip
  // 2 cm into it, fitted to that mesh.
  const TriMesh& body = proceduralBody();
  const ProceduralBodyLandmarks L = proceduralBodyLandmarks();
  const TriMesh garment = makeWrinkledWaistTube(L.waist_y - 0.10, L.waist_y + 0.12, 72, 18, 0.0015, 0.02);
  const SyntheticScan scan = scanOf(body, 60000, 0.001);
  ASSERT_TRUE(scan.success);
  const ScanMeshingResult mesh = meshScan(scan.points, MatrixX3d());
  ASSERT_TRUE(mesh.success) << mesh.message;
  const Body scanned(mesh.mesh);
  const ReferenceReferee truth(body);

  ResolverParams params;
  params.body_uncertainty = mesh.error.p95;
  TriMesh fitted = garment;
  const ResolverReport r = resolvePenetrations(scanned, fitted, params);
  ASSERT_TRUE(r.converged) << r.reason;
  const ReferenceCounts c = truth.count(fitted);
  RecordProperty("clearance_mm", std::to_string(1e3 * r.clearance));
  EXPECT_EQ(c.garment_edge_crossings, 0u);
  EXPECT_EQ(c.body_edge_crossings, 0u);
  EXPECT_EQ(c.vertices_inside, 0u);

  // The same fit that takes the mesh for the surface (clearance d only) is clean against the mesh
  // and not against the truth: what the uncertainty is for. (The paper's rounds alone: the shape
  // relaxation's ARAP turns may lift the tube past the truth by luck, which proves nothing.)
  TriMesh plain = garment;
  ResolverParams plainParams;
  plainParams.objective = ResolverObjective::Paper;
  const ResolverReport p = resolvePenetrations(scanned, plain, plainParams);
  ASSERT_TRUE(p.converged) << p.reason;
  const ReferenceCounts pc = truth.count(plain);
  RecordProperty("plain_truth_crossings", std::to_string(pc.garment_edge_crossings + pc.body_edge_crossings));
  EXPECT_GT(pc.garment_edge_crossings + pc.body_edge_crossings + pc.vertices_inside, 0u);
}
