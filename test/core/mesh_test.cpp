#include "virtual_tryon/core/geometry/mesh.h"
#include "virtual_tryon/core/scenes/procedural.h"
#include "virtual_tryon/testing/reference_check.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

using namespace virtual_tryon;

TEST(Mesh, ValidateNamesTheProblem) {
  TriMesh m;
  EXPECT_FALSE(validate(m, "body").ok);
  EXPECT_NE(validate(m, "body").message.find("body has no vertices"), std::string::npos);
  m.V.resize(3, 3);
  m.V << 0, 0, 0, 1, 0, 0, 0, 1, 0;
  EXPECT_NE(validate(m, "garment").message.find("no faces"), std::string::npos);
  m.F.resize(1, 3);
  m.F << 0, 1, 3;
  MeshValidation v = validate(m, "garment");
  EXPECT_FALSE(v.ok);
  EXPECT_EQ(v.out_of_range_indices, 1u);
  EXPECT_NE(v.message.find("out of range"), std::string::npos) << v.message;
  m.F << 0, 1, -1;
  EXPECT_FALSE(validate(m).ok);
  m.F << 0, 1, 2;
  EXPECT_TRUE(validate(m).ok);
  m.V(1, 2) = std::numeric_limits<double>::quiet_NaN();
  v = validate(m, "garment");
  EXPECT_FALSE(v.ok);
  EXPECT_EQ(v.non_finite_vertices, 1u);
  EXPECT_NE(v.message.find("NaN"), std::string::npos);
}

TEST(Mesh, DegenerateFacesAreCountedNotFatal) {
  TriMesh m;
  m.V.resize(4, 3);
  m.V << 0, 0, 0, 1, 0, 0, 0, 1, 0, 2, 0, 0;
  m.F.resize(3, 3);
  m.F << 0, 1, 2,  // fine
      0, 1, 3,     // collinear: zero area
      2, 2, 0;     // repeated index
  const MeshValidation v = validate(m);
  EXPECT_TRUE(v.ok);
  EXPECT_EQ(v.degenerate_faces, 2u);
}

TEST(Mesh, ProceduralBodiesAreClosedAndOutward) {
  for (const TriMesh& m : {makeSphere(0.5, Eigen::Vector3d(1, 2, 3), 3), makeCapsule(0.1, 0.5),
                           makeCylinder(0.2, 0.3, Eigen::Vector3d::Zero(), 20, 4, true)}) {
    EXPECT_TRUE(validate(m).ok);
    EXPECT_EQ(validate(m).degenerate_faces, 0u);
    EXPECT_TRUE(edgeTopology(m).closed());
    EXPECT_GT(signedVolume(m), 0);
    // Outward: each face normal points away from the centroid.
    const Eigen::RowVector3d c = m.V.colwise().mean();
    const MatrixX3d N = faceNormals(m);
    for (Eigen::Index f = 0; f < m.F.rows(); ++f)
      EXPECT_GT(N.row(f).dot(m.V.row(m.F(f, 0)) - c), 0) << f;
  }
  const double v = signedVolume(makeSphere(1.0, Eigen::Vector3d::Zero(), 4));
  EXPECT_NEAR(v, 4.0 / 3.0 * M_PI, 0.02);
  const EdgeTopology open = edgeTopology(makeCylinder(0.2, 0.3, Eigen::Vector3d::Zero(), 20, 4, false));
  EXPECT_EQ(open.boundary_edges, 40u);
  EXPECT_FALSE(open.closed());
}

TEST(Mesh, BoundaryLoopsOfADiscATubeAndASphere) {
  const TriMesh disc = makePatch(0.1, 0.1, 8, 8, Eigen::Vector3d::Zero());
  const TriMesh tube = makeWrinkledTubeScene(16, 8).garment;
  const TriMesh sphere = makeSphere(0.1, Eigen::Vector3d::Zero(), 2);
  EXPECT_EQ(boundaryLoops(disc), 1u);
  EXPECT_EQ(boundaryLoops(tube), 2u);
  EXPECT_EQ(boundaryLoops(sphere), 0u);
  EXPECT_EQ(boundaryLoops(concatenate(disc, tube)), 3u);
  // The referee counts the same by its own walk.
  for (const TriMesh* m : {&disc, &tube, &sphere}) EXPECT_EQ(referenceBoundaryLoops(*m), boundaryLoops(*m));
  // A face taken out of the disc's middle opens a second loop.
  TriMesh holed = disc;
  Eigen::Index mid = 0;
  double best = INFINITY;
  for (Eigen::Index f = 0; f < disc.F.rows(); ++f) {
    const Eigen::Vector3d c = (disc.V.row(disc.F(f, 0)) + disc.V.row(disc.F(f, 1)) + disc.V.row(disc.F(f, 2))).transpose() / 3;
    if (c.norm() < best) {
      best = c.norm();
      mid = f;
    }
  }
  holed.F.row(mid) = holed.F.row(holed.F.rows() - 1);
  holed.F.conservativeResize(holed.F.rows() - 1, 3);
  EXPECT_EQ(boundaryLoops(holed), referenceBoundaryLoops(holed));
  EXPECT_EQ(boundaryLoops(holed), 2u);
}

TEST(Mesh, EdgesAndComponents) {
  const TriMesh patch = makePatch(1, 1, 3, 2);
  MatrixX3i FE;
  const MatrixX2i E = uniqueEdges(patch, &FE);
  // (nx+1)*nz + (nz+1)*nx + nx*nz diagonals = 4*2 + 3*3 + 6 = 23
  EXPECT_EQ(E.rows(), 23);
  for (Eigen::Index f = 0; f < patch.F.rows(); ++f)
    for (int k = 0; k < 3; ++k) {
      const int a = patch.F(f, k), b = patch.F(f, (k + 1) % 3);
      EXPECT_EQ(E(FE(f, k), 0), std::min(a, b));
      EXPECT_EQ(E(FE(f, k), 1), std::max(a, b));
    }
  std::vector<int> label;
  EXPECT_EQ(connectedComponents(concatenate(patch, makeSphere(0.1)), label), 2);
  EXPECT_NEAR(meanEdgeLength(makePatch(1, 1, 1, 1)), (4 + std::sqrt(2.0)) / 5, 1e-12);
}
