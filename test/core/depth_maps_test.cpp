// Tests of the image-space collision maps (Vassilev et al. 2001, sec. 5-6) on real geometry: an
// icosphere (procedural.h), flat triangulated squares, a box.
#include "virtual_tryon/core/drape/depth_maps.h"
#include "virtual_tryon/core/geometry/mesh.h"
#include "virtual_tryon/core/scenes/procedural.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

namespace vt = virtual_tryon;

namespace {

const double kPi = std::acos(-1.0);

double angleDeg(const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  const double c = a.normalized().dot(b.normalized());
  return std::acos(std::max(-1.0, std::min(1.0, c))) * 180.0 / kPi;
}

// Smallest distance from `c` to the plane of any face: every point of the (inscribed) mesh lies at
// least this far from the centre, so the radial gap to the sphere is at most r - d_min.
double minFacePlaneDistance(const vt::TriMesh& m, const Eigen::Vector3d& c) {
  double d = std::numeric_limits<double>::infinity();
  const vt::MatrixX3d N = vt::faceNormals(m);
  for (Eigen::Index f = 0; f < m.F.rows(); ++f)
    d = std::min(d, std::abs((Eigen::Vector3d(m.V.row(m.F(f, 0))) - c).dot(N.row(f).transpose())));
  return d;
}

// A box with corners lo, hi: 8 vertices, 12 outward counter-clockwise triangles.
vt::TriMesh makeBox(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi) {
  vt::TriMesh m;
  m.V.resize(8, 3);
  for (int i = 0; i < 8; ++i)
    m.V.row(i) << (i & 1 ? hi.x() : lo.x()), (i & 2 ? hi.y() : lo.y()), (i & 4 ? hi.z() : lo.z());
  m.F.resize(12, 3);
  m.F << 0, 2, 1, 1, 2, 3,  // z = lo
      4, 5, 6, 5, 7, 6,     // z = hi
      0, 1, 4, 1, 5, 4,     // y = lo
      2, 6, 3, 3, 6, 7,     // y = hi
      0, 4, 2, 2, 4, 6,     // x = lo
      1, 3, 5, 3, 7, 5;     // x = hi
  return m;
}

// A flat unit square [0,1]^2 at height z, split along the diagonal (0,0)-(1,1) (`main_diagonal`)
// or (1,0)-(0,1); counter-clockwise seen from +z.
vt::TriMesh makeSquare(double z, bool main_diagonal) {
  vt::TriMesh m;
  m.V.resize(4, 3);
  m.V << 0, 0, z, 1, 0, z, 1, 1, z, 0, 1, z;
  m.F.resize(2, 3);
  if (main_diagonal)
    m.F << 0, 1, 2, 0, 2, 3;
  else
    m.F << 0, 1, 3, 1, 2, 3;
  return m;
}

struct SphereFixture : public ::testing::Test {
  const double r = 0.3;
  const Eigen::Vector3d c{0.1, 1.2, -0.05};
  const double tol = 0.005;
  vt::TriMesh mesh = vt::makeSphere(r, c, 5);
  vt::CollisionParams params() const {
    vt::CollisionParams p;
    p.tol = tol;
    p.map_size = 256;
    return p;
  }
};

}  // namespace

// Depth maps against the analytic sphere. The maps are sampled exactly at pixel centres, so the
// only errors are (a) the tessellation: the icosphere is inscribed, each face plane at distance
// >= d (measured from the mesh) from the centre; at a pixel centre at distance rho from the axis,
// with h = sqrt(r^2 - rho^2), a mesh point q over it has |q| >= d and z_q >= sqrt(d^2 - rho^2),
// so h - z_q = (h^2 - z_q^2) / (h + z_q) <= (r^2 - d^2) / (h + sqrt(max(d^2 - rho^2, 0))),
// i.e. about the sagitta (r - d) times r / h; and (b) the vertex snap to 1/256 pixel, far below
// the one-pixel slope term |dz/drho| * pixel = rho / h * pixel that we allow on top (plus 2e-6 for
// the float storage). The mesh lies inside the sphere, so the front can only be low (and the back
// only high) beyond the snap/float slack.
TEST_F(SphereFixture, DepthMapsMatchAnalyticSphere) {
  const vt::DepthMaps dm(mesh, params());
  ASSERT_EQ(dm.mapSize(), 256);
  EXPECT_NEAR(dm.pixelSize(), 2 * r / 256, 1e-9);
  EXPECT_EQ(dm.width(), 258);
  EXPECT_EQ(dm.height(), 258);
  const double px = dm.pixelSize();
  const double d = minFacePlaneDistance(mesh, c);
  ASSERT_GT(d, r * 0.999);  // subdivision 5: sagitta well under 1e-3 r
  int checked = 0, normals_checked = 0;
  double max_err = 0, max_ratio = 0, max_angle = 0;
  for (int Y = 0; Y < dm.height(); ++Y)
    for (int X = 0; X < dm.width(); ++X) {
      const Eigen::Vector2d q = dm.pixelCenter(X, Y);
      const double dx = q.x() - c.x(), dy = q.y() - c.y();
      const double rho = std::hypot(dx, dy);
      if (rho > r - 2 * px) continue;
      const std::size_t i = static_cast<std::size_t>(Y) * dm.width() + X;
      ASSERT_TRUE(dm.filled(X, Y)) << X << " " << Y;
      const double h = std::sqrt(r * r - rho * rho);
      const double tess = (r * r - d * d) / (h + std::sqrt(std::max(d * d - rho * rho, 0.0)));
      const double slope = rho / h;
      const double bound = slope * px + tess + 2e-6;
      const double front_err = (c.z() + h) - (dm.frontDepth()[i] - tol);  // >= 0 up to slack
      const double back_err = (dm.backDepth()[i] + tol) - (c.z() - h);    // >= 0 up to slack
      EXPECT_LE(std::abs(front_err), bound) << X << " " << Y;
      EXPECT_LE(std::abs(back_err), bound) << X << " " << Y;
      EXPECT_GE(front_err, -(slope * px / 100 + 2e-6));
      EXPECT_GE(back_err, -(slope * px / 100 + 2e-6));
      max_err = std::max({max_err, std::abs(front_err), std::abs(back_err)});
      max_ratio = std::max({max_ratio, std::abs(front_err) / bound, std::abs(back_err) / bound});
      ++checked;
      if (rho < 0.9 * r) {  // away from the rim
        const Eigen::Vector3d nf(dx, dy, h), nb(dx, dy, -h);
        const double af = angleDeg(dm.frontNormal()[i].cast<double>(), nf);
        const double ab = angleDeg(dm.backNormal()[i].cast<double>(), nb);
        EXPECT_LT(af, 2.0) << X << " " << Y;
        EXPECT_LT(ab, 2.0) << X << " " << Y;
        EXPECT_NEAR(dm.frontNormal()[i].norm(), 1.0f, 1e-5f);
        max_angle = std::max({max_angle, af, ab});
        ++normals_checked;
      }
    }
  // The disk of radius r - 2 px holds about pi (128 - 2)^2 ~ 49900 centres.
  EXPECT_GT(checked, 49000);
  EXPECT_GT(normals_checked, 39000);
  std::printf("[ sphere   ] %d pixels: max |depth error| %.3g m (%.2f of the bound), max normal error %.3f deg\n",
              checked, max_err, max_ratio, max_angle);
  // Front and back coverage agree, and the covered area is the projected disk (+ the ring).
  std::size_t front_filled = 0, back_filled = 0;
  for (std::size_t i = 0; i < dm.frontDepth().size(); ++i) {
    front_filled += !std::isnan(dm.frontDepth()[i]);
    back_filled += !std::isnan(dm.backDepth()[i]);
  }
  EXPECT_EQ(front_filled, back_filled);
  EXPECT_EQ(front_filled, dm.coveredPixels() + dm.ringPixels());
  EXPECT_NEAR(static_cast<double>(dm.coveredPixels()), kPi * 128 * 128, 2 * kPi * 128);
  EXPECT_GT(dm.buildSeconds(), 0.0);
}

// The one-pixel ring round the silhouette, 8-neighbourhood: a pixel whose centre is less than
// 0.9 px outside the projected disk always has a covered 8-neighbour (the diagonal step toward the
// centre shortens the distance by >= 1 px, less a curvature term ~0.005 px at r = 128 px), so it
// is filled; a pixel whose centre is more than sqrt(2) px outside cannot have one, so it is empty.
TEST_F(SphereFixture, SilhouetteRingIsOnePixelWide) {
  const vt::DepthMaps dm(mesh, params());
  const double px = dm.pixelSize();
  int ring_checked = 0, empty_checked = 0;
  for (int Y = 0; Y < dm.height(); ++Y)
    for (int X = 0; X < dm.width(); ++X) {
      const Eigen::Vector2d q = dm.pixelCenter(X, Y);
      const double delta = (std::hypot(q.x() - c.x(), q.y() - c.y()) - r) / px;
      if (delta > 0.05 && delta <= 0.9) {
        EXPECT_TRUE(dm.filled(X, Y)) << X << " " << Y << " delta " << delta;
        ++ring_checked;
      } else if (delta > 1.5) {
        EXPECT_FALSE(dm.filled(X, Y)) << X << " " << Y << " delta " << delta;
        ++empty_checked;
      }
    }
  EXPECT_GT(ring_checked, 500);
  EXPECT_GT(empty_checked, 10000);
  // The sphere spans pixels 1..256 in x; x = c.x + r is the border of pixels 256 and 257.
  // Half a pixel outside the rim on the x axis: ring pixel, it collides at the equator and its
  // normal points outward (+x).
  const double y_row = c.y() - 0.5 * px;  // the centre of the row just below the equator
  int X = -1, Y = -1;
  ASSERT_TRUE(dm.pixelOf(c.x() + r + 0.5 * px, y_row, X, Y));
  EXPECT_EQ(X, 257);
  EXPECT_TRUE(dm.filled(X, Y));
  Eigen::Vector3d n;
  double depth = -1;
  EXPECT_TRUE(dm.collide(Eigen::Vector3d(c.x() + r + 0.5 * px, y_row, c.z()), n, &depth));
  EXPECT_GT(n.x(), 0.95);
  EXPECT_NEAR(n.norm(), 1.0, 1e-6);
  EXPECT_GT(depth, tol);
  // The same on the -y side (pixel row 0 is the ring below the sphere).
  ASSERT_TRUE(dm.pixelOf(c.x() + 0.5 * px, c.y() - r - 0.5 * px, X, Y));
  EXPECT_EQ(Y, 0);
  EXPECT_TRUE(dm.filled(X, Y));
  EXPECT_TRUE(dm.collide(Eigen::Vector3d(c.x() + 0.5 * px, c.y() - r - 0.5 * px, c.z()), n));
  EXPECT_LT(n.y(), -0.95);
  // One and a half pixels outside on the x axis is already beyond the one-pixel margin: outside
  // the map, no collision.
  EXPECT_FALSE(dm.pixelOf(c.x() + r + 1.5 * px, y_row, X, Y));
  EXPECT_FALSE(dm.collide(Eigen::Vector3d(c.x() + r + 1.5 * px, y_row, c.z()), n));
  // Diagonally the map extends further: 2.5 px outside the rim at 45 degrees the pixel centre is
  // >= 2.5 - sqrt(2)/2 > sqrt(2) px out, so the pixel is inside the map but empty.
  const Eigen::Vector3d diag = c + (r + 2.5 * px) * Eigen::Vector3d(1, 1, 0).normalized();
  ASSERT_TRUE(dm.pixelOf(diag.x(), diag.y(), X, Y));
  EXPECT_FALSE(dm.filled(X, Y));
  EXPECT_FALSE(dm.collide(diag, n));
  // ... while at 0.15 px outside it the pixel centre is < 0.15 + sqrt(2)/2 < 0.9 px out: filled.
  const Eigen::Vector3d near_rim = c + (r + 0.15 * px) * Eigen::Vector3d(1, 1, 0).normalized();
  EXPECT_TRUE(dm.collide(near_rim, n));
  EXPECT_GT(n.dot(Eigen::Vector3d(1, 1, 0).normalized()), 0.95);
  EXPECT_GT(dm.ringPixels(), 0u);
}

TEST_F(SphereFixture, CollideInsideOutsideAndNormals) {
  const vt::DepthMaps dm(mesh, params());
  const double px = dm.pixelSize();
  Eigen::Vector3d n;
  double depth = -1;
  // The centre: deep inside; the depth is the distance to the nearer shell surface, r + tol.
  ASSERT_TRUE(dm.collide(c, n, &depth));
  EXPECT_NEAR(depth, r + tol, 1e-3);
  EXPECT_NEAR(n.norm(), 1.0, 1e-6);
  // Two tolerances in front of the front pole: free.
  EXPECT_FALSE(dm.collide(c + Eigen::Vector3d(0, 0, r + 2 * tol), n, &depth));
  EXPECT_FALSE(dm.collide(c - Eigen::Vector3d(0, 0, r + 2 * tol), n, &depth));
  // Half a tolerance outside the front surface (inside the shell): collides, front normal.
  const double ox = 0.1, oy = 0.05, h = std::sqrt(r * r - ox * ox - oy * oy);
  const Eigen::Vector3d analytic_front(ox / r, oy / r, h / r);
  depth = -1;
  ASSERT_TRUE(dm.collide(c + Eigen::Vector3d(ox, oy, h + 0.5 * tol), n, &depth));
  EXPECT_LT(angleDeg(n, analytic_front), 2.0);
  EXPECT_GT(n.z(), 0.8);
  // depth ~ tol / 2, up to the slope over (at most) 0.71 px: (rho / h) 0.71 px ~ 0.7 mm.
  EXPECT_NEAR(depth, 0.5 * tol, (std::hypot(ox, oy) / h) * 0.71 * px + 1e-4);
  // Mirror on the back: back normal.
  ASSERT_TRUE(dm.collide(c + Eigen::Vector3d(ox, oy, -h - 0.5 * tol), n, &depth));
  EXPECT_LT(angleDeg(n, Eigen::Vector3d(ox / r, oy / r, -h / r)), 2.0);
  EXPECT_LT(n.z(), -0.8);
  // Just inside the front surface, still nearer the front: front normal.
  ASSERT_TRUE(dm.collide(c + Eigen::Vector3d(ox, oy, h - 0.01), n, &depth));
  EXPECT_GT(n.z(), 0.8);
  EXPECT_NEAR(depth, 0.01 + tol, 2e-3);
  // Outside the map (beyond the box and the margin), NaN: false.
  EXPECT_FALSE(dm.collide(c + Eigen::Vector3d(r + 3 * px, 0, 0), n));
  EXPECT_FALSE(dm.collide(c + Eigen::Vector3d(0, -r - 3 * px, 0), n));
  EXPECT_FALSE(dm.collide(c + Eigen::Vector3d(10, 0, 0), n));
  EXPECT_FALSE(dm.collide(c + Eigen::Vector3d(0, 10, 0), n));
  EXPECT_FALSE(dm.collide(Eigen::Vector3d(std::nan(""), c.y(), c.z()), n));
  // Inside the map but an empty corner pixel (the box corner is outside the disk).
  EXPECT_FALSE(dm.collide(c + Eigen::Vector3d(r - px, r - px, 0), n));
  // Outputs untouched on a miss.
  n = Eigen::Vector3d(7, 7, 7);
  depth = 42;
  EXPECT_FALSE(dm.collide(c + Eigen::Vector3d(10, 0, 0), n, &depth));
  EXPECT_EQ(n, Eigen::Vector3d(7, 7, 7));
  EXPECT_EQ(depth, 42);
}

TEST_F(SphereFixture, ResponseAtTheFrontPole) {
  const vt::DepthMaps dm(mesh, params());
  Eigen::Vector3d n;
  ASSERT_TRUE(dm.collide(c + Eigen::Vector3d(0, 0, r), n));
  EXPECT_LT(angleDeg(n, Eigen::Vector3d::UnitZ()), 1.0);
  const double fr = 0.8, re = 0.1;
  // Moving in: tangential part scaled by friction, normal part reflected and scaled.
  const Eigen::Vector3d v(1, 0, -2);
  EXPECT_TRUE(vt::collisionResponse(v, Eigen::Vector3d::UnitZ(), fr, re).isApprox(Eigen::Vector3d(0.8, 0, 0.2)));
  EXPECT_LT((vt::collisionResponse(v, n, fr, re) - Eigen::Vector3d(0.8, 0, 0.2)).norm(), 0.05);
  // Leaving: normal part kept, tangential part scaled.
  EXPECT_TRUE(vt::collisionResponse(Eigen::Vector3d(1, 0, 2), Eigen::Vector3d::UnitZ(), fr, re)
                  .isApprox(Eigen::Vector3d(0.8, 0, 2)));
  // Purely tangential: friction only.
  EXPECT_TRUE(vt::collisionResponse(Eigen::Vector3d(0, 3, 0), Eigen::Vector3d::UnitZ(), fr, re)
                  .isApprox(Eigen::Vector3d(0, 2.4, 0)));
  // A general normal: the response's normal component is -C_refl times the incoming one.
  const Eigen::Vector3d m = Eigen::Vector3d(1, 2, 2).normalized();
  const Eigen::Vector3d w(0.3, -1.0, -0.5);
  const Eigen::Vector3d res = vt::collisionResponse(w, m, fr, re);
  EXPECT_NEAR(res.dot(m), -re * w.dot(m), 1e-12);
  EXPECT_TRUE((res - res.dot(m) * m).isApprox(fr * (w - w.dot(m) * m)));
}

TEST(DepthMaps, MapSizeFromTolerance) {
  const vt::TriMesh box = makeBox(Eigen::Vector3d(-0.25, 0, -0.15), Eigen::Vector3d(0.25, 1.7, 0.15));
  EXPECT_EQ(vt::mapSizeForTolerance(box, 0.005), 340);
  EXPECT_EQ(vt::mapSizeForTolerance(box, 0.0051), 334);  // ceil(333.33)
  EXPECT_EQ(vt::mapSizeForTolerance(box, 1.0), 16);       // clamped
  EXPECT_EQ(vt::mapSizeForTolerance(box, 1e-5), 4096);    // clamped
  EXPECT_EQ(vt::mapSizeForTolerance(box, 0.0), 4096);
  vt::CollisionParams p;
  p.tol = 0.005;
  const vt::DepthMaps dm(box, p);
  EXPECT_EQ(dm.mapSize(), 340);
  EXPECT_NEAR(dm.pixelSize(), 0.005, 1e-12);
  EXPECT_EQ(dm.height(), 340 + 2);
  EXPECT_EQ(dm.width(), 100 + 2);
  EXPECT_NEAR(dm.originX(), -0.25 - 0.005, 1e-12);
  EXPECT_NEAR(dm.originY(), -0.005, 1e-12);
  // The box fills its whole rectangle: 100 x 340 covered, plus the ring (the full margin).
  EXPECT_EQ(dm.coveredPixels(), 100u * 340u);
  EXPECT_EQ(dm.ringPixels(), 102u * 342u - 100u * 340u);
  Eigen::Vector3d n;
  double depth;
  ASSERT_TRUE(dm.collide(Eigen::Vector3d(0.1, 1.0, 0.15 + 0.004), n, &depth));
  EXPECT_NEAR(depth, 0.001, 1e-6);
  EXPECT_GT(n.z(), 0.3);  // smooth (interpolated corner) normals, tilted but facing +z
  EXPECT_FALSE(dm.collide(Eigen::Vector3d(0.1, 1.0, 0.15 + 0.006), n));
  // World <-> pixel round trip.
  int X, Y;
  ASSERT_TRUE(dm.pixelOf(0.1, 1.0, X, Y));
  const Eigen::Vector2d q = dm.pixelCenter(X, Y);
  EXPECT_LE(std::abs(q.x() - 0.1), 0.5 * dm.pixelSize() + 1e-12);
  EXPECT_LE(std::abs(q.y() - 1.0), 0.5 * dm.pixelSize() + 1e-12);
}

// No cracks: pixel centres exactly on the shared diagonal are covered. With map_size 64 the
// square [0,1]^2 gets pixel 1/64 and origin -1/64, so the centre of pixel (X, Y) is
// ((X - 1/2) / 64, (Y - 1/2) / 64): all 64 centres with X == Y (resp. X + Y == 65) lie exactly on
// the diagonal. Every centre inside the square must be covered, with the plane's depth.
TEST(DepthMaps, NoCracksOnSharedDiagonal) {
  for (bool main_diagonal : {true, false}) {
    const double z = 0.2, tol = 0.005;
    const vt::TriMesh sq = makeSquare(z, main_diagonal);
    vt::CollisionParams p;
    p.tol = tol;
    p.map_size = 64;
    const vt::DepthMaps dm(sq, p);
    ASSERT_EQ(dm.width(), 66);
    ASSERT_EQ(dm.height(), 66);
    int on_diagonal = 0;
    for (int Y = 1; Y <= 64; ++Y)
      for (int X = 1; X <= 64; ++X) {
        const Eigen::Vector2d q = dm.pixelCenter(X, Y);
        if (main_diagonal ? q.x() == q.y() : q.x() + q.y() == 1.0) ++on_diagonal;
        const std::size_t i = static_cast<std::size_t>(Y) * dm.width() + X;
        ASSERT_TRUE(dm.filled(X, Y)) << X << " " << Y;
        EXPECT_FLOAT_EQ(dm.frontDepth()[i], static_cast<float>(z + tol));
        EXPECT_FLOAT_EQ(dm.backDepth()[i], static_cast<float>(z - tol));
        EXPECT_LT(angleDeg(dm.frontNormal()[i].cast<double>(), Eigen::Vector3d::UnitZ()), 1e-3);
      }
    EXPECT_EQ(on_diagonal, 64);
    EXPECT_EQ(dm.coveredPixels(), 64u * 64u);
    EXPECT_EQ(dm.ringPixels(), 66u * 66u - 64u * 64u);
  }
}

// A triangulated square whose interior vertices sit exactly on pixel centres (so whole rows and
// columns of centres lie on shared edges, and centres sit on vertices shared by six triangles),
// in both windings: every interior centre is covered.
TEST(DepthMaps, NoCracksAtSharedVerticesAndEdges) {
  const int n = 8, map = 64;
  for (bool flip : {false, true}) {
    vt::TriMesh m;
    m.V.resize((n + 1) * (n + 1), 3);
    auto coord = [&](int i) {  // boundary on the square's edges, interior on centre columns
      if (i == 0 || i == n) return static_cast<double>(i) / n;
      return (8.0 * i - 0.5) / map;
    };
    for (int j = 0; j <= n; ++j)
      for (int i = 0; i <= n; ++i) m.V.row(j * (n + 1) + i) << coord(i), coord(j), 0.1 * coord(i);
    m.F.resize(2 * n * n, 3);
    int f = 0;
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i) {
        const int a = j * (n + 1) + i, b = a + 1, c = a + n + 2, d = a + n + 1;
        if ((i + j) % 2 == 0) {
          m.F.row(f++) << a, b, c;
          m.F.row(f++) << a, c, d;
        } else {
          m.F.row(f++) << a, b, d;
          m.F.row(f++) << b, c, d;
        }
      }
    if (flip) m.F.col(1).swap(m.F.col(2));
    vt::CollisionParams p;
    p.map_size = map;
    const vt::DepthMaps dm(m, p);
    for (int Y = 1; Y <= map; ++Y)
      for (int X = 1; X <= map; ++X) {
        ASSERT_TRUE(dm.filled(X, Y)) << X << " " << Y << (flip ? " flipped" : "");
        const Eigen::Vector2d q = dm.pixelCenter(X, Y);
        const std::size_t i = static_cast<std::size_t>(Y) * dm.width() + X;
        EXPECT_NEAR(dm.frontDepth()[i], 0.1 * q.x() + p.tol, 1e-6);  // the plane z = 0.1 x
      }
    EXPECT_EQ(dm.coveredPixels(), static_cast<std::size_t>(map * map));
  }
}

// Non-finite-free output on a sphere: filled pixels have front >= back and unit normals; empty
// ones are NaN in both maps.
TEST_F(SphereFixture, MapsAreConsistent) {
  vt::CollisionParams p = params();
  p.map_size = 0;  // from tol: 0.6 / 0.005 = 120
  const vt::DepthMaps dm(mesh, p);
  EXPECT_EQ(dm.mapSize(), 120);
  for (std::size_t i = 0; i < dm.frontDepth().size(); ++i) {
    const float f = dm.frontDepth()[i], b = dm.backDepth()[i];
    ASSERT_EQ(std::isnan(f), std::isnan(b));
    if (std::isnan(f)) continue;
    EXPECT_GE(f, b + 2 * tol - 1e-6);
    EXPECT_NEAR(dm.frontNormal()[i].norm(), 1.0f, 1e-5f);
    EXPECT_NEAR(dm.backNormal()[i].norm(), 1.0f, 1e-5f);
    EXPECT_GE(dm.frontNormal()[i].z(), -1e-3f);  // the visible front faces +z
    EXPECT_LE(dm.backNormal()[i].z(), 1e-3f);
  }
  // A loose speed sanity check (the measured figure is a few ms; this only catches blow-ups).
  EXPECT_LT(dm.buildSeconds(), 1.0);
}

// The top view sees what the front view cannot: a "boot" at heel strike, the shin column on a foot
// block reaching forward along z, its toes raised (a post at the front). A point over the foot,
// between the shin and the toes, lies between the heel's back and the toes' front, so the front
// maps call it inside, 4 cm deep; from above it lies over the foot's top, outside. A point inside
// the shin is inside in both views, and the top view's normal on the foot's top, turned back to
// the world, points up.
TEST(DepthMaps, TopViewSeesTheHollowAboveAFoot) {
  const vt::TriMesh shin = vt::makeCylinder(0.05, 0.40, Eigen::Vector3d(0, 0.25, 0), 32, 8);
  const vt::TriMesh foot = vt::transformed(vt::makeCylinder(0.03, 0.24, Eigen::Vector3d::Zero(), 32, 8),
                                           Eigen::Vector3d::UnitX(), M_PI / 2, Eigen::Vector3d(0, 0.03, 0.08));
  const vt::TriMesh toes = vt::makeCylinder(0.025, 0.16, Eigen::Vector3d(0, 0.08, 0.175), 32, 8);
  const vt::TriMesh boot = vt::concatenate(vt::concatenate(shin, foot), toes);
  vt::CollisionParams cp;
  cp.tol = 0.003;
  const vt::DepthMaps front(boot, cp);
  const vt::DepthMaps top(vt::viewMesh(vt::MapView::Top, boot), cp);
  Eigen::Vector3d n;
  double depth = 0;
  const Eigen::Vector3d hollow(0, 0.10, 0.10);  // above the foot (its top at y 0.06), shin to toes
  ASSERT_TRUE(front.collide(hollow, n, &depth));
  EXPECT_GT(depth, 0.04);
  EXPECT_FALSE(top.collide(vt::viewPoint(vt::MapView::Top, hollow), n, &depth));
  const Eigen::Vector3d inShin(0, 0.30, 0.01);
  EXPECT_TRUE(front.collide(inShin, n, &depth));
  EXPECT_TRUE(top.collide(vt::viewPoint(vt::MapView::Top, inShin), n, &depth));
  const Eigen::Vector3d onFoot(0, 0.059, 0.10);  // just under the foot's top, shin to toes
  ASSERT_TRUE(top.collide(vt::viewPoint(vt::MapView::Top, onFoot), n, &depth));
  const Eigen::Vector3d up = vt::worldDirection(vt::MapView::Top, n);
  EXPECT_GT(up.y(), 0.9) << up.transpose();
  EXPECT_LT(depth, 0.003 + 0.002);
}

// Velocity maps: an affine field v(x) = A x + c given at the vertices is interpolated over each
// pixel's winning face, which for a flat face is the field itself at the surface point under the
// pixel centre: front and back, every covered pixel (the ring ones copy a neighbour).
TEST(DepthMaps, VelocityMapsHoldTheSkinsVelocityAtTheSurface) {
  const vt::TriMesh sphere = vt::makeSphere(0.3, Eigen::Vector3d(0.1, 1.0, -0.2), 4);
  Eigen::Matrix3d A;
  A << 0.0, -0.5, 0.2, 0.5, 0.0, -0.1, -0.2, 0.1, 0.3;
  const Eigen::Vector3d c(0.3, -0.2, 0.1);
  vt::MatrixX3d VV(sphere.V.rows(), 3);
  for (Eigen::Index i = 0; i < sphere.V.rows(); ++i) VV.row(i) = (A * sphere.V.row(i).transpose() + c).transpose();
  vt::CollisionParams cp;
  cp.tol = 0.004;
  const vt::DepthMaps plain(sphere, cp);
  EXPECT_FALSE(plain.hasVelocity());
  const vt::DepthMaps dm(sphere, cp, plain.grid(), VV);
  ASSERT_TRUE(dm.hasVelocity());
  std::size_t checked = 0;
  double worst = 0;
  for (int Y = 1; Y + 1 < dm.height(); ++Y)
    for (int X = 1; X + 1 < dm.width(); ++X) {
      const std::size_t i = static_cast<std::size_t>(Y) * dm.width() + X;
      if (!dm.filled(X, Y) || !plain.filled(X, Y)) continue;
      // Covered, not ring: all eight neighbours filled too (a ring pixel has an empty neighbour).
      bool interior = true;
      for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx) interior = interior && dm.filled(X + dx, Y + dy);
      if (!interior) continue;
      const Eigen::Vector2d xy = dm.pixelCenter(X, Y);
      const Eigen::Vector3d pf(xy.x(), xy.y(), dm.frontDepth()[i] - cp.tol), pb(xy.x(), xy.y(), dm.backDepth()[i] + cp.tol);
      worst = std::max(worst, (dm.frontVelocity()[i].cast<double>() - (A * pf + c)).norm());
      worst = std::max(worst, (dm.backVelocity()[i].cast<double>() - (A * pb + c)).norm());
      ++checked;
    }
  EXPECT_GT(checked, 1000u);
  EXPECT_LT(worst, 1e-4) << "over " << checked << " pixels";
  // The depths and normals are those of the maps without velocity.
  EXPECT_EQ(dm.frontDepth().size(), plain.frontDepth().size());
  for (std::size_t i = 0; i < dm.frontDepth().size(); ++i)
    if (!std::isnan(plain.frontDepth()[i])) ASSERT_EQ(dm.frontDepth()[i], plain.frontDepth()[i]);
}
