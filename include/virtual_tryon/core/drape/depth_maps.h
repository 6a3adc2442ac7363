// Image-space collision maps (Vassilev et al. 2001, sec. 5): the body rendered once by two
// orthographic cameras, front (+z) and back (-z), into depth maps and smoothly interpolated normal
// maps; a cloth point is tested by looking up its pixel.
//
// Conventions: the body's bounding box [x_min, x_max] x [y_min, y_max] x [z_min, z_max] (metres,
// y up, the body faces +z). Pixels are square, of side
//   dx = max(x_max - x_min, y_max - y_min) / map_size,
// and the map has a one-pixel margin on every side (room for the silhouette ring):
//   x0 = x_min - dx,  y0 = y_min - dx,
//   width  = ceil((x_max - x_min) / dx) + 2,  height = ceil((y_max - y_min) / dx) + 2,
// so the longer side is map_size + 2 pixels. Pixel (X, Y) covers
//   x in [x0 + X dx, x0 + (X+1) dx),  y in [y0 + Y dx, y0 + (Y+1) dx)
// (Y grows with y, i.e. row 0 is the bottom of the body); the world point p lies in pixel
// X = floor((p.x - x0) / dx), Y = floor((p.y - y0) / dx), and the map is sampled at the pixel
// centre (x0 + (X + 1/2) dx, y0 + (Y + 1/2) dx).
//
// front(X, Y) = the largest z of the body surface over the pixel centre + tol;
// back(X, Y)  = the smallest z - tol (world z, not normalized). The normal maps hold the unit
// outward body normal at the same surface points (area-weighted vertex normals interpolated
// barycentrically, then normalized). Pixels the body does not cover are empty (NaN), except that
// one ring of pixels round the silhouette is filled from its covered neighbours, so the sides get
// the tolerance too (see DepthMaps below).
#pragma once

#include "virtual_tryon/core/geometry/mesh.h"

#include <cmath>
#include <cstddef>
#include <vector>

namespace virtual_tryon {

struct CollisionParams {
  double tol = 0.005;          // tolerance added front, back and (one pixel ring) at the sides, m
  int map_size = 0;            // pixels along the longer side of the box; 0: derived from tol
  double friction = 0.8;       // C_fric: kept fraction of the tangential velocity
  double reflection = 0.1;     // C_refl: reflected fraction of the normal velocity
};

// The map size that makes one pixel = tol (the paper's choice): ceil(longer x/y extent of the
// bounding box / tol), clamped to [16, 4096] (4096 also when tol is not positive).
int mapSizeForTolerance(const TriMesh& body, double tol);

// The pixel grid of a pair of maps: map_size pixels along the longer side of a box, a one-pixel
// margin round it (see the conventions above). Maps rendered on the same grid (a moving body's
// frames, DepthMaps' second constructor) share their pixels, so that a pixel can be interpolated
// between them.
struct MapGrid {
  int width = 0, height = 0, map_size = 0;
  double pixel = 0, x0 = 0, y0 = 0;  // m: pixel side, world x, y of the corner of pixel (0, 0)
  // True when the box [lo, hi] (its x and y) lies inside the grid, margin excluded.
  bool holds(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi) const;
};

// The grid of the box [lo, hi] with map_size pixels along its longer x-y side (>= 1).
MapGrid mapGridFor(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi, int mapSize, double tol);

// Other orthographic views of a body, each a rotation q = R p of the world (faces keep their
// orientation) that makes another world axis the maps' depth axis (q.z):
//   Front: q = p (the paper's view, depth along z);
//   Top:   q = (x, -z, y), depth along y: the front map holds the body's tops, the back map its
//          undersides, over the x-z plane;
//   Side:  q = (-z, y, x), depth along x: the front map holds the body's left sides (+x), the back
//          map its right, over the z-y plane.
// DepthMaps of viewMesh(v, body) are looked up at viewPoint(v, p). A point inside the body lies
// inside every view's depth interval; one that lies outside any is outside the body (the front
// view alone cannot see a hollow along z, such as the gap above a raised foot in front of the
// shin, or between an arm swung back and the torso).
enum class MapView { Front, Top, Side };
inline Eigen::Vector3d viewPoint(MapView v, const Eigen::Vector3d& p) {
  switch (v) {
    case MapView::Top: return Eigen::Vector3d(p.x(), -p.z(), p.y());
    case MapView::Side: return Eigen::Vector3d(-p.z(), p.y(), p.x());
    default: return p;
  }
}
// A direction of view v's frame (a normal of its maps) in the world: R^T n.
inline Eigen::Vector3d worldDirection(MapView v, const Eigen::Vector3d& n) {
  switch (v) {
    case MapView::Top: return Eigen::Vector3d(n.x(), n.z(), -n.y());
    case MapView::Side: return Eigen::Vector3d(n.z(), n.y(), -n.x());
    default: return n;
  }
}
TriMesh viewMesh(MapView v, const TriMesh& body);

class DepthMaps {
 public:
  // Renders both maps with a CPU z-buffer rasterizer. `body` must be valid. The map size is
  // params.map_size when positive (capped at 16384), else mapSizeForTolerance(body, params.tol).
  //
  // Rasterization: orthographic along z, every triangle of either orientation (no culling, so
  // open scans work), sampled at pixel centres. Vertices are snapped to a fixed-point grid of
  // 1/256 pixel and the edge functions are evaluated exactly in 64-bit integers with a
  // top-left-style fill rule: a centre strictly inside is covered; a centre exactly on an edge is
  // covered by exactly one of the two triangles sharing that edge (the edge a->b of the
  // counter-clockwise-in-x-y triangle is owned when b.y < a.y, or b.y == a.y and b.x < a.x;
  // the reversed edge of the neighbour then is not). So two triangles lying on either side of a
  // shared edge in the projection cover a centre on it exactly once, likewise the fan round a
  // shared vertex: a watertight surface leaves no cracks and is not double-counted. Triangles
  // with zero projected area are skipped (their neighbours cover the same centres).
  // Pass 2 interpolates the vertex normals of each pixel's winning face at the pixel centre.
  //
  // Silhouette ring: after adding tol, every empty pixel with at least one covered 8-neighbour
  // (Chebyshev distance 1, so there are no gaps at the diagonal steps of the silhouette) is
  // filled: front = the largest front of its covered neighbours, back = the smallest back (the
  // conservative, thickest choice). Each ring normal is the normal of the neighbour that gave the
  // depth, blended half-way toward the outward x-y direction o from that neighbour's pixel to the
  // ring pixel: normalize(n_neighbour + o) (o unit, z = 0); if that sum vanishes, o itself. Only
  // one ring; ring pixels do not seed further rings.
  DepthMaps(const TriMesh& body, const CollisionParams& params);
  // The same on a given grid (for example a box round every frame of a moving body), which should
  // hold the body (MapGrid::holds): what lies outside is not rendered. map_size of params is not
  // read.
  DepthMaps(const TriMesh& body, const CollisionParams& params, const MapGrid& grid);
  // The same with velocity maps: `vertexVelocity` (#V by 3, m/s, e.g. a moving body's vertices'
  // change over a frame / its duration) interpolated barycentrically over each pixel's winning
  // face at the pixel centre, front and back (a ring pixel takes its neighbour's), the material
  // velocity of the surface there.
  DepthMaps(const TriMesh& body, const CollisionParams& params, const MapGrid& grid, const MatrixX3d& vertexVelocity);

  // The grid these maps are rendered on.
  MapGrid grid() const {
    MapGrid g;
    g.width = width_;
    g.height = height_;
    g.map_size = map_size_;
    g.pixel = pixel_;
    g.x0 = x0_;
    g.y0 = y0_;
    return g;
  }
  // The pixel index [Y * width + X] of world (x, y); false when outside the map.
  bool pixelIndex(double x, double y, std::size_t& i) const {
    const double u = (x - x0_) * inv_pixel_, v = (y - y0_) * inv_pixel_;
    if (!(u >= 0.0 && u < width_ && v >= 0.0 && v < height_)) return false;
    i = static_cast<std::size_t>(static_cast<int>(v)) * static_cast<std::size_t>(width_) +
        static_cast<std::size_t>(static_cast<int>(u));
    return true;
  }

  // True when p collides: its pixel is covered (or in the ring) and back <= z <= front. `normal`
  // then receives the body's outward normal there: from the front map when p is nearer the front
  // surface ((front - z) <= (z - back)), else from the back map. `depth` (optional) receives
  // min(front - z, z - back): how far p lies inside the tolerance shell along z (>= 0). Points
  // outside the map (or NaN) and empty pixels: false, outputs untouched. No allocation.
  bool collide(const Eigen::Vector3d& p, Eigen::Vector3d& normal, double* depth = nullptr) const {
    const double u = (p.x() - x0_) * inv_pixel_;
    const double v = (p.y() - y0_) * inv_pixel_;
    if (!(u >= 0.0 && u < width_ && v >= 0.0 && v < height_)) return false;
    const std::size_t i =
        static_cast<std::size_t>(static_cast<int>(v)) * static_cast<std::size_t>(width_) +
        static_cast<std::size_t>(static_cast<int>(u));
    const double f = front_[i], b = back_[i];
    const double z = p.z();
    if (!(z <= f && z >= b)) return false;  // also false for empty (NaN) pixels
    const double df = f - z, db = z - b;
    normal = (df <= db ? front_n_[i] : back_n_[i]).cast<double>();
    if (depth) *depth = df <= db ? df : db;
    return true;
  }

  int width() const { return width_; }
  int height() const { return height_; }
  int mapSize() const { return map_size_; }  // pixels along the longer side, without the margin
  double pixelSize() const { return pixel_; }
  double tol() const { return tol_; }
  const Eigen::Vector3d& boxMin() const { return lo_; }  // the body's bounding box
  const Eigen::Vector3d& boxMax() const { return hi_; }
  double originX() const { return x0_; }  // world x, y of the corner of pixel (0, 0)
  double originY() const { return y0_; }
  double buildSeconds() const { return build_seconds_; }
  std::size_t coveredPixels() const { return covered_; }  // covered by the body itself
  std::size_t ringPixels() const { return ring_; }        // filled by the silhouette ring

  // The pixel holding world (x, y); false when outside the map.
  bool pixelOf(double x, double y, int& X, int& Y) const {
    const double u = (x - x0_) * inv_pixel_, v = (y - y0_) * inv_pixel_;
    if (!(u >= 0.0 && u < width_ && v >= 0.0 && v < height_)) return false;
    X = static_cast<int>(u);
    Y = static_cast<int>(v);
    return true;
  }
  // World x, y of the centre of pixel (X, Y).
  Eigen::Vector2d pixelCenter(int X, int Y) const {
    return Eigen::Vector2d(x0_ + (X + 0.5) * pixel_, y0_ + (Y + 0.5) * pixel_);
  }
  // True when pixel (X, Y) is inside the map and not empty (covered or ring).
  bool filled(int X, int Y) const {
    return X >= 0 && Y >= 0 && X < width_ && Y < height_ &&
           !std::isnan(front_[static_cast<std::size_t>(Y) * width_ + X]);
  }

  // Raw maps for tests and pictures, row-major [Y * width + X]; empty pixels hold NaN (depths)
  // and (0, 0, 0) (normals).
  const std::vector<float>& frontDepth() const { return front_; }
  const std::vector<float>& backDepth() const { return back_; }
  const std::vector<Eigen::Vector3f>& frontNormal() const { return front_n_; }
  const std::vector<Eigen::Vector3f>& backNormal() const { return back_n_; }
  // Velocity maps (the constructor with vertex velocities; else empty), (0, 0, 0) where empty.
  bool hasVelocity() const { return !front_v_.empty(); }
  const std::vector<Eigen::Vector3f>& frontVelocity() const { return front_v_; }
  const std::vector<Eigen::Vector3f>& backVelocity() const { return back_v_; }

 private:
  void render(const TriMesh& body, const CollisionParams& params, const MapGrid& grid,
              const MatrixX3d* vertexVelocity = nullptr);

  int width_ = 0, height_ = 0, map_size_ = 0;
  double pixel_ = 0, inv_pixel_ = 0, tol_ = 0, build_seconds_ = 0;
  double x0_ = 0, y0_ = 0;
  std::size_t covered_ = 0, ring_ = 0;
  Eigen::Vector3d lo_, hi_;
  std::vector<float> front_, back_;
  std::vector<Eigen::Vector3f> front_n_, back_n_;
  std::vector<Eigen::Vector3f> front_v_, back_v_;
};

// The paper's response (eq. 12). With v_n = (v . n) n and v_t = v - v_n:
//   v . n < 0 (moving into the body):  v_res = C_fric v_t - C_refl v_n  (normal part reflected);
//   otherwise (already leaving):        v_res = C_fric v_t + v_n        (friction only).
// n must be unit.
Eigen::Vector3d collisionResponse(const Eigen::Vector3d& v, const Eigen::Vector3d& n,
                                  double friction, double reflection);

}  // namespace virtual_tryon
