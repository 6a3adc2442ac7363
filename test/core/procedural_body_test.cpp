#include "virtual_tryon/core/geometry/mesh.h"
#include "virtual_tryon/core/scenes/procedural_body.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <vector>

using namespace virtual_tryon;

namespace {

constexpr double kPi = 3.14159265358979323846;

const TriMesh& defaultBody() {
  static const TriMesh body = makeProceduralBody();
  return body;
}

Eigen::Vector3d sdfGradient(const Eigen::Vector3d& p, const ProceduralBodyParams& params) {
  const double h = 1e-4;
  Eigen::Vector3d g;
  for (int k = 0; k < 3; ++k) {
    Eigen::Vector3d e = Eigen::Vector3d::Zero();
    e(k) = h;
    g(k) = (proceduralBodySdf(p + e, params) - proceduralBodySdf(p - e, params)) / (2 * h);
  }
  return g;
}

// Closed, manifold, outward, one piece, no degenerate faces, no unused vertices.
void expectCleanClosedMesh(const TriMesh& m, const char* what) {
  SCOPED_TRACE(what);
  ASSERT_FALSE(m.empty());
  const MeshValidation v = validate(m, what);
  EXPECT_TRUE(v.ok) << v.message;
  EXPECT_EQ(v.degenerate_faces, 0u) << v.message;
  EXPECT_EQ(v.unused_vertices, 0u) << v.message;
  const EdgeTopology t = edgeTopology(m);
  EXPECT_EQ(t.boundary_edges, 0u);
  EXPECT_EQ(t.non_manifold_edges, 0u);
  std::vector<int> label;
  EXPECT_EQ(connectedComponents(m, label), 1);
  EXPECT_GT(signedVolume(m), 0.0);
  // Closed 2-manifold of genus 0: V - E + F = 2 (the body is a sphere topologically).
  const MatrixX2i E = uniqueEdges(m);
  EXPECT_EQ(m.V.rows() - E.rows() + m.F.rows(), 2);
}

double height(const TriMesh& m) {
  Eigen::Vector3d lo, hi;
  boundingBox(m, lo, hi);
  return hi.y() - lo.y();
}

}  // namespace

TEST(ProceduralBody, DefaultBodyIsClosedManifoldOutwardOnePiece) {
  const TriMesh& m = defaultBody();
  expectCleanClosedMesh(m, "body");
  // Default resolution (1.5 cm): tens of thousands of triangles.
  EXPECT_GT(m.F.rows(), 20000);
  EXPECT_LT(m.F.rows(), 100000);
}

TEST(ProceduralBody, FeetOnTheGroundAndHeight) {
  for (double h : {1.70, 1.50}) {
    ProceduralBodyParams p;
    p.height = h;
    const TriMesh m = h == 1.70 ? defaultBody() : makeProceduralBody(p);
    Eigen::Vector3d lo, hi;
    boundingBox(m, lo, hi);
    EXPECT_NEAR(lo.y(), 0.0, 0.01) << "height " << h;
    EXPECT_NEAR(hi.y() - lo.y(), h, 0.01) << "height " << h;
    // Symmetric about x = 0, facing +z (the feet stick out to the front).
    EXPECT_NEAR(lo.x(), -hi.x(), 0.01);
    EXPECT_GT(hi.z(), -lo.z());
    if (h != 1.70) expectCleanClosedMesh(m, "1.50 m body");
  }
}

TEST(ProceduralBody, CoarseResolutionsStayInOnePiece) {
  for (double res : {0.025, 0.03, 0.04}) {
    ProceduralBodyParams p;
    p.resolution = res;
    const TriMesh m = makeProceduralBody(p);
    const EdgeTopology t = edgeTopology(m);
    EXPECT_TRUE(t.closed()) << res;
    std::vector<int> label;
    EXPECT_EQ(connectedComponents(m, label), 1) << res;
    EXPECT_EQ(validate(m).degenerate_faces, 0u) << res;
    EXPECT_NEAR(height(m), 1.70, 0.02) << res;
  }
}

TEST(ProceduralBody, SdfFollowsTheParameters) {
  ProceduralBodyParams tall, short_;
  short_.height = 1.50;
  const Eigen::Vector3d aboveShortHead(0.0, 1.55, 0.0);
  // Alternate between parameter sets (the primitives are cached per thread).
  for (int i = 0; i < 2; ++i) {
    EXPECT_LT(proceduralBodySdf(aboveShortHead, tall), 0.0);
    EXPECT_GT(proceduralBodySdf(aboveShortHead, short_), 0.0);
  }
  // Roughly a distance near the surface: one centimetre above the head is about 0.01 outside.
  EXPECT_NEAR(proceduralBodySdf(Eigen::Vector3d(0.0, 1.71, 0.0008)), 0.01, 0.003);
  EXPECT_NEAR(proceduralBodySdf(Eigen::Vector3d(0.0, 1.60 * 1.50 / 1.70, 0.0), short_),
              proceduralBodySdf(Eigen::Vector3d(0.0, 1.60, 0.0)) * 1.50 / 1.70, 1e-12);
}

TEST(ProceduralBody, VolumeIsPlausible) {
  const double v170 = signedVolume(defaultBody());
  EXPECT_GT(v170, 0.055);
  EXPECT_LT(v170, 0.085);
  // Everything scales with the height.
  ProceduralBodyParams p;
  p.height = 1.50;
  p.resolution = 0.015 * 1.50 / 1.70;
  const double v150 = signedVolume(makeProceduralBody(p));
  EXPECT_NEAR(v150 / v170, std::pow(1.50 / 1.70, 3), 0.02 * std::pow(1.50 / 1.70, 3));
}

TEST(ProceduralBody, GirthScaleChangesVolumeAndStaysClean) {
  ProceduralBodyParams thin, thick;
  thin.girth_scale = 0.85;
  thick.girth_scale = 1.25;
  thin.resolution = thick.resolution = 0.02;
  const TriMesh a = makeProceduralBody(thin), b = makeProceduralBody(thick);
  expectCleanClosedMesh(a, "thin body");
  expectCleanClosedMesh(b, "thick body");
  EXPECT_LT(signedVolume(a), 0.9 * signedVolume(defaultBody()));
  EXPECT_GT(signedVolume(b), 1.2 * signedVolume(defaultBody()));
  EXPECT_NEAR(height(b), 1.70, 0.01);
}

TEST(ProceduralBody, MeshFollowsTheImplicitSurfaceAndFacesOutward) {
  const ProceduralBodyParams params;
  const TriMesh& m = defaultBody();
  double worst = 0;
  for (Eigen::Index i = 0; i < m.V.rows(); ++i)
    worst = std::max(worst, std::abs(proceduralBodySdf(m.V.row(i).transpose(), params)));
  EXPECT_LT(worst, 0.5 * params.resolution);
  // Face normals agree with the SDF gradient (a handful of slivers in the most curved places may
  // deviate: the mesh is the piecewise-linear level set, not the exact one).
  const MatrixX3d N = faceNormals(m);
  Eigen::Index agree = 0, wellAligned = 0;
  for (Eigen::Index f = 0; f < m.F.rows(); ++f) {
    const Eigen::Vector3d c =
        (m.V.row(m.F(f, 0)) + m.V.row(m.F(f, 1)) + m.V.row(m.F(f, 2))).transpose() / 3.0;
    const double d = N.row(f).dot(sdfGradient(c, params).normalized());
    if (d > 0) ++agree;
    if (d > 0.5) ++wellAligned;
  }
  EXPECT_GE(agree, m.F.rows() - m.F.rows() / 1000);
  EXPECT_GE(wellAligned, m.F.rows() - m.F.rows() / 100);
}

TEST(ProceduralBody, LandmarksAreConsistent) {
  const ProceduralBodyParams params;
  const ProceduralBodyLandmarks L = proceduralBodyLandmarks(params);
  auto sdf = [&](const Eigen::Vector3d& p) { return proceduralBodySdf(p, params); };

  // Heights in anatomical order.
  EXPECT_LT(0.0, L.knee_y);
  EXPECT_LT(L.knee_y, L.crotch_y);
  EXPECT_LT(L.crotch_y, L.hip_y);
  EXPECT_LT(L.hip_y, L.waist_y);
  EXPECT_LT(L.waist_y, L.chest_y);
  EXPECT_LT(L.chest_y, L.shoulder_y);
  EXPECT_LT(L.shoulder_y, L.neck_y);
  EXPECT_LT(L.neck_y, params.height);

  // Waist narrower than hips and chest; plausible sizes (full widths and depths).
  EXPECT_LT(L.waist_radius_x, L.hip_radius_x);
  EXPECT_LT(L.waist_radius_x, L.chest_radius_x);
  EXPECT_LT(L.waist_radius_z, L.chest_radius_z);
  EXPECT_GT(2 * L.chest_radius_x, 0.31);
  EXPECT_LT(2 * L.chest_radius_x, 0.37);
  EXPECT_NEAR(2 * L.chest_radius_z, 0.22, 0.02);
  EXPECT_GT(2 * L.hip_radius_x, 0.33);
  EXPECT_LT(2 * L.hip_radius_x, 0.39);
  for (double r : {L.waist_radius_x, L.waist_radius_z, L.hip_radius_x, L.hip_radius_z, L.chest_radius_x,
                   L.chest_radius_z}) {
    EXPECT_GT(r, 0.05);
    EXPECT_LT(r, 0.25);
  }

  // The half-widths are on the surface.
  const double tol = 1e-4;
  EXPECT_NEAR(sdf({L.waist_radius_x, L.waist_y, L.waist_z}), 0.0, tol);
  EXPECT_NEAR(sdf({-L.waist_radius_x, L.waist_y, L.waist_z}), 0.0, tol);
  EXPECT_NEAR(sdf({0.0, L.waist_y, L.waist_z + L.waist_radius_z}), 0.0, tol);
  EXPECT_NEAR(sdf({0.0, L.waist_y, L.waist_z - L.waist_radius_z}), 0.0, tol);
  EXPECT_NEAR(sdf({L.hip_radius_x, L.hip_y, L.hip_z}), 0.0, tol);
  EXPECT_NEAR(sdf({0.0, L.hip_y, L.hip_z + L.hip_radius_z}), 0.0, tol);
  EXPECT_NEAR(sdf({L.chest_radius_x, L.chest_y, L.chest_z}), 0.0, tol);
  EXPECT_NEAR(sdf({0.0, L.chest_y, L.chest_z - L.chest_radius_z}), 0.0, tol);
  EXPECT_NEAR(sdf({0.0, L.crotch_y, L.hip_z}), 0.0, 1e-3);

  // Joints are inside the body; left is +x, mirror-symmetric.
  for (const Eigen::Vector3d& p :
       {L.left_shoulder, L.right_shoulder, L.left_elbow, L.right_elbow, L.left_wrist, L.right_wrist, L.left_hand,
        L.right_hand, L.left_hip_joint, L.right_hip_joint, L.left_knee, L.right_knee, L.left_ankle,
        L.right_ankle})
    EXPECT_LE(sdf(p), 1e-3) << p.transpose();
  EXPECT_GT(L.left_shoulder.x(), 0.0);
  EXPECT_GT(L.left_hand.x(), 0.0);
  EXPECT_GT(L.left_hip_joint.x(), 0.0);
  EXPECT_TRUE(L.left_hand.isApprox(Eigen::Vector3d(-L.right_hand.x(), L.right_hand.y(), L.right_hand.z())));
  EXPECT_TRUE(L.left_ankle.isApprox(Eigen::Vector3d(-L.right_ankle.x(), L.right_ankle.y(), L.right_ankle.z())));
  EXPECT_NEAR(L.left_shoulder.y(), L.shoulder_y, 1e-12);
  EXPECT_NEAR(L.left_knee.y(), L.knee_y, 1e-12);
  EXPECT_LT(L.left_ankle.y(), L.knee_y);
  EXPECT_LT(L.left_hip_joint.y(), L.waist_y);
  EXPECT_GT(L.left_hip_joint.y(), L.crotch_y);

  // Radii: the surface is one radius away from the limb axis.
  EXPECT_GT(L.arm_radius, 0.03);
  EXPECT_LT(L.arm_radius, L.thigh_radius);
  EXPECT_GT(L.thigh_radius, 0.06);
  EXPECT_LT(L.thigh_radius, 0.11);

  // A-pose: hands below the shoulders, outside the hips, arm 40-45 degrees below the horizontal.
  for (int side = 0; side < 2; ++side) {
    const Eigen::Vector3d sh = side == 0 ? L.left_shoulder : L.right_shoulder;
    const Eigen::Vector3d hand = side == 0 ? L.left_hand : L.right_hand;
    const Eigen::Vector3d wrist = side == 0 ? L.left_wrist : L.right_wrist;
    EXPECT_LT(hand.y(), sh.y() - 0.2);
    EXPECT_GT(std::abs(hand.x()), L.hip_radius_x + 0.08);
    const double angle = std::atan2(sh.y() - wrist.y(), std::abs(wrist.x() - sh.x())) * 180.0 / kPi;
    EXPECT_GE(angle, 40.0 - 1e-9);
    EXPECT_LE(angle, 45.0 + 1e-9);
  }
}

TEST(ProceduralBody, GapsBetweenArmsAndTorsoAndBetweenThighs) {
  const ProceduralBodyParams params;
  const ProceduralBodyLandmarks L = proceduralBodyLandmarks(params);
  auto sdf = [&](const Eigen::Vector3d& p) { return proceduralBodySdf(p, params); };
  // At the hand's height, walking from the hand towards the body axis: the longest run of empty
  // space between hand and hip is at least 8 cm.
  for (const Eigen::Vector3d& hand : {L.left_hand, L.right_hand}) {
    const double sx = hand.x() > 0 ? 1.0 : -1.0;
    double run = 0, longest = 0;
    const double step = 0.001;
    for (double x = std::abs(hand.x()); x >= 0; x -= step) {
      if (sdf({sx * x, hand.y(), hand.z()}) > 0) {
        run += step;
        longest = std::max(longest, run);
      } else {
        run = 0;
      }
    }
    EXPECT_GE(longest, 0.08) << "hand at " << hand.transpose();
  }
  // Just below the crotch, between the thighs, is outside.
  EXPECT_GT(sdf({0.0, L.crotch_y - 0.02, L.hip_z}), 0.0);
  EXPECT_GT(sdf({0.0, L.knee_y, 0.0}), 0.0);
}

TEST(MeshImplicit, SphereIsAccurateClosedAndOutward) {
  const double r = 0.3, cell = 0.03;
  const Eigen::Vector3d c(0.1, -0.2, 0.05);
  auto f = [&](const Eigen::Vector3d& p) { return (p - c).norm() - r; };
  const TriMesh m = meshImplicit(f, c.array() - r - 2 * cell, c.array() + r + 2 * cell, cell);
  expectCleanClosedMesh(m, "sphere");
  for (Eigen::Index i = 0; i < m.V.rows(); ++i)
    ASSERT_NEAR((m.V.row(i).transpose() - c).norm(), r, 0.02 * r) << "vertex " << i;
  const double exact = 4.0 / 3.0 * kPi * r * r * r;
  EXPECT_NEAR(signedVolume(m), exact, 0.03 * exact);
  const MatrixX3d N = faceNormals(m);
  for (Eigen::Index fi = 0; fi < m.F.rows(); ++fi) {
    const Eigen::Vector3d centroid =
        (m.V.row(m.F(fi, 0)) + m.V.row(m.F(fi, 1)) + m.V.row(m.F(fi, 2))).transpose() / 3.0;
    ASSERT_GT(N.row(fi).dot((centroid - c).normalized()), 0.0) << "face " << fi;
  }
}

TEST(MeshImplicit, SurfaceThroughGridNodesHasNoDegenerateFaces) {
  // A cube whose faces pass exactly through grid nodes (f = 0 at many nodes).
  const double cell = 0.05, half = 0.2;
  auto f = [&](const Eigen::Vector3d& p) { return p.cwiseAbs().maxCoeff() - half; };
  const TriMesh m = meshImplicit(f, Eigen::Vector3d::Constant(-0.35), Eigen::Vector3d::Constant(0.35), cell);
  expectCleanClosedMesh(m, "cube");
  // The edges and corners are chamfered by the linear interpolation: somewhat less than (2 half)^3.
  const double v = signedVolume(m);
  EXPECT_LT(v, std::pow(2 * half, 3) * 1.001);
  EXPECT_GT(v, std::pow(2 * half, 3) * 0.9);
}

TEST(MeshImplicit, TwoSeparateBlobsGiveTwoComponentsAndEmptyGivesEmpty) {
  auto two = [](const Eigen::Vector3d& p) {
    return std::min((p - Eigen::Vector3d(-0.3, 0, 0)).norm(), (p - Eigen::Vector3d(0.3, 0, 0)).norm()) - 0.15;
  };
  const TriMesh m = meshImplicit(two, Eigen::Vector3d(-0.5, -0.2, -0.2), Eigen::Vector3d(0.5, 0.2, 0.2), 0.025);
  EXPECT_TRUE(edgeTopology(m).closed());
  std::vector<int> label;
  EXPECT_EQ(connectedComponents(m, label), 2);
  EXPECT_GT(signedVolume(m), 0.0);

  auto none = [](const Eigen::Vector3d& p) { return p.norm() + 1.0; };
  EXPECT_TRUE(meshImplicit(none, Eigen::Vector3d::Constant(-1), Eigen::Vector3d::Constant(1), 0.1).empty());
  EXPECT_TRUE(meshImplicit(two, Eigen::Vector3d::Constant(1), Eigen::Vector3d::Constant(-1), 0.1).empty());
}

TEST(SubdivideMidpoint, QuadruplesFacesKeepsClosedAndVolume) {
  ProceduralBodyParams p;
  p.resolution = 0.03;
  const TriMesh m = makeProceduralBody(p);
  const TriMesh s = subdivideMidpoint(m);
  EXPECT_EQ(s.F.rows(), 4 * m.F.rows());
  EXPECT_EQ(s.V.rows(), m.V.rows() + uniqueEdges(m).rows());
  EXPECT_TRUE(s.V.topRows(m.V.rows()) == m.V);  // original vertices untouched
  expectCleanClosedMesh(s, "subdivided body");
  EXPECT_NEAR(signedVolume(s), signedVolume(m), 1e-12 * signedVolume(m));
  // Winding preserved: every child face has its parent's normal.
  const MatrixX3d N0 = faceNormals(m), N1 = faceNormals(s);
  for (Eigen::Index f = 0; f < m.F.rows(); ++f)
    for (int k = 0; k < 4; ++k) ASSERT_GT(N0.row(f).dot(N1.row(4 * f + k)), 1.0 - 1e-6) << "face " << f;
  // Edge lengths halve on average.
  EXPECT_NEAR(meanEdgeLength(s), 0.5 * meanEdgeLength(m), 0.1 * meanEdgeLength(m));
}
