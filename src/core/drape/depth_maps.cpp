#include "virtual_tryon/core/drape/depth_maps.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <limits>

namespace virtual_tryon {

namespace {

constexpr int kSubBits = 8;                    // fixed point: 1/256 pixel
constexpr std::int64_t kSub = 1 << kSubBits;   // one pixel in fixed-point units
constexpr std::int64_t kHalf = kSub / 2;       // pixel centre offset
constexpr float kInf = std::numeric_limits<float>::infinity();
constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();

// The 8-neighbourhood of the silhouette ring: offsets (kDX[k], kDY[k]).
constexpr int kDX[8] = {1, -1, 0, 0, 1, 1, -1, -1};
constexpr int kDY[8] = {0, 0, 1, -1, 1, -1, 1, -1};

// floor(a / kSub) and ceil(a / kSub) (kSub a power of two; >> of a negative int64 is an arithmetic
// shift on every compiler we target, and well defined from C++20).
inline std::int64_t floorSub(std::int64_t a) { return a >> kSubBits; }
inline std::int64_t ceilSub(std::int64_t a) { return -((-a) >> kSubBits); }

// The maps being built: DepthMaps' buffers, row-major [Y * width + X].
struct MapBuffers {
  int width, height;
  std::vector<float>& front;
  std::vector<float>& back;
  std::vector<Eigen::Vector3f>& front_n;
  std::vector<Eigen::Vector3f>& back_n;
  std::vector<Eigen::Vector3f>& front_v;  // empty: no velocity maps
  std::vector<Eigen::Vector3f>& back_v;

  std::size_t W() const { return static_cast<std::size_t>(width); }
  // Index of the neighbour k (kDX, kDY) of pixel i.
  std::size_t neighbour(std::size_t i, int k) const {
    return i + static_cast<std::size_t>(static_cast<std::ptrdiff_t>(kDY[k]) * width + kDX[k]);
  }
  void clear(std::size_t i) {
    front[i] = back[i] = kNaN;
    front_n[i].setZero();
    back_n[i].setZero();
    if (!front_v.empty()) {
      front_v[i].setZero();
      back_v[i].setZero();
    }
  }
};

// During pass 1 the normal maps (not initialized) hold the id of the winning face in their first
// float.
inline void setId(Eigen::Vector3f& slot, int id) { std::memcpy(slot.data(), &id, sizeof id); }
inline int getId(const Eigen::Vector3f& slot) {
  int id;
  std::memcpy(&id, slot.data(), sizeof id);
  return id;
}

// Per rasterized face: the interpolated (unnormalized) vertex normal as an affine function of
// the pixel indices, relative to the face's first pixel (X0, Y0), for pass 2.
struct NormalField {
  float n0[3], dX[3], dY[3];
  int X0, Y0, face;
};

// Edge function of edge p->q at s: (q - p) x (s - p), >= 0 on the left (inside), exact.
// Fill rule: owned edges accept 0, the others need > 0, i.e. E - bias >= 0, bias 0 or 1.
struct Edge {
  std::int64_t row, stepX, stepY, bias;
};

// The edge p->q evaluated at the centre (sx0, sy0) of the face's first pixel.
Edge makeEdge(std::int64_t px, std::int64_t py, std::int64_t qx, std::int64_t qy, std::int64_t sx0,
              std::int64_t sy0) {
  const std::int64_t dx = qx - px, dy = qy - py;
  const bool owned = dy < 0 || (dy == 0 && dx < 0);
  Edge e;
  e.bias = owned ? 0 : 1;
  e.row = dx * (sy0 - py) - dy * (sx0 - px) - e.bias;
  e.stepX = -dy * kSub;
  e.stepY = dx * kSub;
  return e;
}

// One face ready to scan: its vertices counter-clockwise in x-y, the pixel range whose centres
// fall in its box, and its edges at the first pixel (e[0] = area * barycentric weight of a, e[1]
// of b, e[2] of c).
struct FaceRaster {
  int ia, ib, ic;
  std::int64_t X0, X1, Y0, Y1, area;
  Edge e[3];
};

// False when the face covers no pixel centre or has zero projected area.
bool setUpFace(const TriMesh& body, Eigen::Index f, const std::vector<std::int32_t>& fx,
               const std::vector<std::int32_t>& fy, int width, int height, FaceRaster& r) {
  r.ia = body.F(f, 0);
  r.ib = body.F(f, 1);
  r.ic = body.F(f, 2);
  const std::int64_t ax = fx[r.ia], ay = fy[r.ia];
  std::int64_t bx = fx[r.ib], by = fy[r.ib], cx = fx[r.ic], cy = fy[r.ic];
  // Pixel range whose centres (X kSub + kHalf) fall in the triangle's box; most triangles of a
  // fine mesh at a coarse map hold no centre at all and stop here.
  r.X0 = std::max<std::int64_t>(0, ceilSub(std::min({ax, bx, cx}) - kHalf));
  r.X1 = std::min<std::int64_t>(width - 1, floorSub(std::max({ax, bx, cx}) - kHalf));
  if (r.X0 > r.X1) return false;
  r.Y0 = std::max<std::int64_t>(0, ceilSub(std::min({ay, by, cy}) - kHalf));
  r.Y1 = std::min<std::int64_t>(height - 1, floorSub(std::max({ay, by, cy}) - kHalf));
  if (r.Y0 > r.Y1) return false;
  r.area = (bx - ax) * (cy - ay) - (by - ay) * (cx - ax);
  if (r.area == 0) return false;
  if (r.area < 0) {  // make it counter-clockwise in x-y
    std::swap(r.ib, r.ic);
    std::swap(bx, cx);
    std::swap(by, cy);
    r.area = -r.area;
  }
  const std::int64_t sx0 = r.X0 * kSub + kHalf, sy0 = r.Y0 * kSub + kHalf;
  r.e[0] = makeEdge(bx, by, cx, cy, sx0, sy0);
  r.e[1] = makeEdge(cx, cy, ax, ay, sx0, sy0);
  r.e[2] = makeEdge(ax, ay, bx, by, sx0, sy0);
  return true;
}

// Barycentric weights at (X0, Y0) and their steps along X and Y; z and the normal are affine in
// them.
struct Barycentric {
  double w0, w1, w2, gx0, gx1, gx2, gy0, gy1, gy2;
};

Barycentric barycentric(const FaceRaster& r) {
  const Edge &e0 = r.e[0], &e1 = r.e[1], &e2 = r.e[2];
  const double inv_area = 1.0 / static_cast<double>(r.area);
  Barycentric b;
  b.w0 = static_cast<double>(e0.row + e0.bias) * inv_area;
  b.w1 = static_cast<double>(e1.row + e1.bias) * inv_area;
  b.w2 = static_cast<double>(e2.row + e2.bias) * inv_area;
  b.gx0 = static_cast<double>(e0.stepX) * inv_area;
  b.gx1 = static_cast<double>(e1.stepX) * inv_area;
  b.gx2 = static_cast<double>(e2.stepX) * inv_area;
  b.gy0 = static_cast<double>(e0.stepY) * inv_area;
  b.gy1 = static_cast<double>(e1.stepY) * inv_area;
  b.gy2 = static_cast<double>(e2.stepY) * inv_area;
  return b;
}

NormalField normalField(const FaceRaster& r, Eigen::Index f, const Barycentric& b, const MatrixX3d& VN) {
  NormalField nf;
  nf.X0 = static_cast<int>(r.X0);
  nf.Y0 = static_cast<int>(r.Y0);
  nf.face = static_cast<int>(f);
  for (int k = 0; k < 3; ++k) {
    const double na = VN(r.ia, k), nb = VN(r.ib, k), nc = VN(r.ic, k);
    nf.n0[k] = static_cast<float>(b.w0 * na + b.w1 * nb + b.w2 * nc);
    nf.dX[k] = static_cast<float>(b.gx0 * na + b.gx1 * nb + b.gx2 * nc);
    nf.dY[k] = static_cast<float>(b.gy0 * na + b.gy1 * nb + b.gy2 * nc);
  }
  return nf;
}

// z-buffers the face's covered centres into both maps, storing `id` where it wins.
void scanFace(const TriMesh& body, const FaceRaster& r, const Barycentric& b, int id, MapBuffers& maps) {
  Edge e0 = r.e[0], e1 = r.e[1], e2 = r.e[2];
  const double za = body.V(r.ia, 2), zb = body.V(r.ib, 2), zc = body.V(r.ic, 2);
  double zrow = b.w0 * za + b.w1 * zb + b.w2 * zc;
  const double dzX = b.gx0 * za + b.gx1 * zb + b.gx2 * zc;
  const double dzY = b.gy0 * za + b.gy1 * zb + b.gy2 * zc;
  for (std::int64_t Y = r.Y0; Y <= r.Y1; ++Y) {
    std::int64_t E0 = e0.row, E1 = e1.row, E2 = e2.row;
    double z = zrow;
    std::size_t idx = static_cast<std::size_t>(Y) * maps.W() + static_cast<std::size_t>(r.X0);
    for (std::int64_t X = r.X0; X <= r.X1; ++X, ++idx) {
      if ((E0 | E1 | E2) >= 0) {
        const float zf = static_cast<float>(z);
        if (zf > maps.front[idx]) {
          maps.front[idx] = zf;
          setId(maps.front_n[idx], id);
        }
        if (zf < maps.back[idx]) {
          maps.back[idx] = zf;
          setId(maps.back_n[idx], id);
        }
      }
      E0 += e0.stepX;
      E1 += e1.stepX;
      E2 += e2.stepX;
      z += dzX;
    }
    e0.row += e0.stepY;
    e1.row += e1.stepY;
    e2.row += e2.stepY;
    zrow += dzY;
  }
}

// Pass 1: z-buffers both maps at once; `fields` receives the normal field of every rasterized
// face, indexed by the id the maps hold.
void rasterize(const TriMesh& body, double x0, double y0, double inv_pixel, MapBuffers& maps,
               std::vector<NormalField>& fields) {
  // Vertices in fixed-point pixel coordinates (x right, y up).
  const Eigen::Index nv = body.V.rows();
  // (|values| < 16386 * 256 < 2^31; the products below are formed in 64 bits.)
  std::vector<std::int32_t> fx(static_cast<std::size_t>(nv)), fy(static_cast<std::size_t>(nv));
  const double scale = inv_pixel * kSub;
  for (Eigen::Index i = 0; i < nv; ++i) {
    // Rounded to nearest; the values are >= one pixel (the margin), so truncating u + 1/2 does it.
    fx[i] = static_cast<std::int32_t>((body.V(i, 0) - x0) * scale + 0.5);
    fy[i] = static_cast<std::int32_t>((body.V(i, 1) - y0) * scale + 0.5);
  }
  const MatrixX3d VN = vertexNormals(body);
  fields.reserve(static_cast<std::size_t>(body.F.rows()));  // reserve touches no memory
  FaceRaster r;
  for (Eigen::Index f = 0; f < body.F.rows(); ++f) {
    if (!setUpFace(body, f, fx, fy, maps.width, maps.height, r)) continue;
    const Barycentric b = barycentric(r);
    const int id = static_cast<int>(fields.size());  // what the maps store during pass 1
    fields.push_back(normalField(r, f, b, VN));
    scanFace(body, r, b, id, maps);
  }
}

// The unit normal of field `nf` at pixel (X, Y).
Eigen::Vector3f fieldNormal(const TriMesh& body, const NormalField& nf, int X, int Y) {
  const float u = static_cast<float>(X - nf.X0), v = static_cast<float>(Y - nf.Y0);
  Eigen::Vector3f n(nf.n0[0] + u * nf.dX[0] + v * nf.dY[0], nf.n0[1] + u * nf.dX[1] + v * nf.dY[1],
                    nf.n0[2] + u * nf.dX[2] + v * nf.dY[2]);
  const float len2 = n.squaredNorm();
  if (len2 > 1e-12f) return n / std::sqrt(len2);
  // Opposite vertex normals cancel here (a crease): the face normal instead.
  const int face = nf.face;
  const Eigen::Vector3d pa = body.V.row(body.F(face, 0)), pb = body.V.row(body.F(face, 1)),
                        pc = body.V.row(body.F(face, 2));
  const Eigen::Vector3d g = (pb - pa).cross(pc - pa);
  const double len = g.norm();
  return len > 0 ? Eigen::Vector3f((g / len).cast<float>()) : Eigen::Vector3f::Zero();
}

// Where a map's velocities come from: the vertices' velocities, and the grid's world x, y.
struct VelocitySource {
  const MatrixX3d* V = nullptr;  // #V by 3; null: no velocity maps
  double x0 = 0, y0 = 0, pixel = 0;
};

// The vertex velocities of `face` interpolated at the centre of pixel (X, Y) (barycentric in x-y,
// the weights clamped to the face).
Eigen::Vector3f faceVelocity(const TriMesh& body, int face, int X, int Y, const VelocitySource& vs) {
  const double px = vs.x0 + (X + 0.5) * vs.pixel, py = vs.y0 + (Y + 0.5) * vs.pixel;
  const Eigen::Index a = body.F(face, 0), b = body.F(face, 1), c = body.F(face, 2);
  const double ax = body.V(a, 0), ay = body.V(a, 1), bx = body.V(b, 0), by = body.V(b, 1);
  const double cx = body.V(c, 0), cy = body.V(c, 1);
  const double area = (bx - ax) * (cy - ay) - (cx - ax) * (by - ay);
  if (!(std::abs(area) > 0)) return ((vs.V->row(a) + vs.V->row(b) + vs.V->row(c)) / 3.0).transpose().cast<float>();
  double wa = ((bx - px) * (cy - py) - (cx - px) * (by - py)) / area;
  double wb = ((cx - px) * (ay - py) - (ax - px) * (cy - py)) / area;
  double wc = 1.0 - wa - wb;
  wa = std::clamp(wa, 0.0, 1.0);
  wb = std::clamp(wb, 0.0, 1.0);
  wc = std::clamp(wc, 0.0, 1.0);
  const double sum = wa + wb + wc;
  return ((wa * vs.V->row(a) + wb * vs.V->row(b) + wc * vs.V->row(c)) / sum).transpose().cast<float>();
}

// Pass 2: normals (and velocities) of the winning faces, tol. Empty pixels stay -inf / +inf for
// now. Returns the number of covered pixels.
std::size_t fillNormals(const TriMesh& body, const std::vector<NormalField>& fields, double tol,
                        MapBuffers& maps, const VelocitySource& vs) {
  auto normalOf = [&](int id, int X, int Y) {
    return fieldNormal(body, fields[static_cast<std::size_t>(id)], X, Y);
  };
  auto velocityOf = [&](int id, int X, int Y) {
    return faceVelocity(body, fields[static_cast<std::size_t>(id)].face, X, Y, vs);
  };
  const float ftol = static_cast<float>(tol);
  std::size_t covered = 0;
  for (int Y = 0; Y < maps.height; ++Y) {
    std::size_t i = static_cast<std::size_t>(Y) * maps.W();
    for (int X = 0; X < maps.width; ++X, ++i) {
      if (!(maps.front[i] > -kInf)) continue;
      ++covered;
      if (vs.V) {
        maps.front_v[i] = velocityOf(getId(maps.front_n[i]), X, Y);
        maps.back_v[i] = velocityOf(getId(maps.back_n[i]), X, Y);
      }
      maps.front_n[i] = normalOf(getId(maps.front_n[i]), X, Y);
      maps.back_n[i] = normalOf(getId(maps.back_n[i]), X, Y);
      maps.front[i] += ftol;
      maps.back[i] -= ftol;
    }
  }
  return covered;
}

// A ring pixel and the neighbours (kDX, kDY index) that give its front and back.
struct RingPixel {
  std::size_t i;
  int kf, kb;
};

// True when the empty interior pixel i has no covered 8-neighbour (most empty pixels): a fast
// rejection away from the silhouette.
bool farFromSilhouette(const MapBuffers& maps, std::size_t i) {
  const std::size_t W = maps.W();
  const float* up = &maps.front[i + W];
  const float* mid = &maps.front[i];
  const float* down = &maps.front[i - W];
  const bool any = (up[-1] > -kInf) | (up[0] > -kInf) | (up[1] > -kInf) | (mid[-1] > -kInf) |
                   (mid[1] > -kInf) | (down[-1] > -kInf) | (down[0] > -kInf) | (down[1] > -kInf);
  return !any;
}

// The covered 8-neighbours of (X, Y) with the largest front (kf) and the smallest back (kb); -1
// when there is none.
void bestNeighbours(const MapBuffers& maps, int X, int Y, int& kf, int& kb) {
  kf = kb = -1;
  float best_f = -kInf, best_b = kInf;
  for (int k = 0; k < 8; ++k) {
    const int nx = X + kDX[k], ny = Y + kDY[k];
    if (nx < 0 || ny < 0 || nx >= maps.width || ny >= maps.height) continue;
    const std::size_t j = static_cast<std::size_t>(ny) * maps.W() + static_cast<std::size_t>(nx);
    if (!(maps.front[j] > -kInf)) continue;
    if (maps.front[j] > best_f) {
      best_f = maps.front[j];
      kf = k;
    }
    if (maps.back[j] < best_b) {
      best_b = maps.back[j];
      kb = k;
    }
  }
}

// The ring pixels with their neighbours, from the covered pixels (front > -inf); every other
// empty pixel becomes NaN.
std::vector<RingPixel> findRing(MapBuffers& maps) {
  std::vector<RingPixel> ring;
  for (int Y = 0; Y < maps.height; ++Y) {
    std::size_t i = static_cast<std::size_t>(Y) * maps.W();
    for (int X = 0; X < maps.width; ++X, ++i) {
      if (maps.front[i] > -kInf) continue;  // covered
      if (X > 0 && Y > 0 && X + 1 < maps.width && Y + 1 < maps.height && farFromSilhouette(maps, i)) {
        maps.clear(i);
        continue;
      }
      int kf = -1, kb = -1;
      bestNeighbours(maps, X, Y, kf, kb);
      if (kf >= 0) {
        ring.push_back({i, kf, kb});
      } else {
        maps.clear(i);
      }
    }
  }
  return ring;
}

// The normal of ring pixel i from its neighbour k: blended half-way toward the outward direction.
Eigen::Vector3f ringNormal(const MapBuffers& maps, std::size_t i, int k,
                           const std::vector<Eigen::Vector3f>& normals) {
  const std::size_t j = maps.neighbour(i, k);
  // Outward: from the neighbour to this pixel, i.e. minus the offset to the neighbour.
  const Eigen::Vector3f o =
      Eigen::Vector3f(static_cast<float>(-kDX[k]), static_cast<float>(-kDY[k]), 0.f).normalized();
  const Eigen::Vector3f s = normals[j] + o;
  const float len = s.norm();
  return len > 1e-6f ? Eigen::Vector3f(s / len) : o;
}

// Pass 3: one silhouette ring (8-neighbourhood) from the covered pixels (front > -inf; the ring is
// applied afterwards, so it does not seed itself). Empty pixels become NaN, which also fails
// "> -inf". Returns the number of ring pixels.
std::size_t fillRing(MapBuffers& maps) {
  const std::vector<RingPixel> ring = findRing(maps);
  for (const RingPixel& r : ring) {
    const std::size_t jf = maps.neighbour(r.i, r.kf);
    const std::size_t jb = maps.neighbour(r.i, r.kb);
    maps.front[r.i] = maps.front[jf];
    maps.back[r.i] = maps.back[jb];
    maps.front_n[r.i] = ringNormal(maps, r.i, r.kf, maps.front_n);
    maps.back_n[r.i] = ringNormal(maps, r.i, r.kb, maps.back_n);
    if (!maps.front_v.empty()) {
      maps.front_v[r.i] = maps.front_v[jf];
      maps.back_v[r.i] = maps.back_v[jb];
    }
  }
  return ring.size();
}

}  // namespace

int mapSizeForTolerance(const TriMesh& body, double tol) {
  if (!(tol > 0)) return 4096;
  Eigen::Vector3d lo, hi;
  boundingBox(body, lo, hi);
  const double extent = std::max(hi.x() - lo.x(), hi.y() - lo.y());
  if (!(extent > 0)) return 16;
  // The small slack keeps exact ratios (1.7 / 0.005 = 340) from rounding up to the next integer.
  const double n = std::ceil(extent / tol - 1e-9);
  if (!(n < 4096)) return 4096;
  return std::max(16, static_cast<int>(n));
}

MapGrid mapGridFor(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi, int mapSize, double tol) {
  MapGrid g;
  const double ex = hi.x() - lo.x(), ey = hi.y() - lo.y();
  const double extent = std::max(ex, ey);
  g.map_size = mapSize;
  g.pixel = extent > 0 ? extent / mapSize : (tol > 0 ? tol : 1e-3);
  // Same slack as mapSizeForTolerance: the longer side gets exactly map_size pixels.
  const int inner_w = std::max(1, static_cast<int>(std::ceil(ex / g.pixel - 1e-9)));
  const int inner_h = std::max(1, static_cast<int>(std::ceil(ey / g.pixel - 1e-9)));
  g.width = inner_w + 2;
  g.height = inner_h + 2;
  g.x0 = lo.x() - g.pixel;
  g.y0 = lo.y() - g.pixel;
  return g;
}

bool MapGrid::holds(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi) const {
  return width > 2 && lo.x() >= x0 + pixel && lo.y() >= y0 + pixel && hi.x() <= x0 + (width - 1) * pixel &&
         hi.y() <= y0 + (height - 1) * pixel;
}

DepthMaps::DepthMaps(const TriMesh& body, const CollisionParams& params) {
  Eigen::Vector3d lo, hi;
  boundingBox(body, lo, hi);
  const int size = params.map_size > 0 ? std::min(params.map_size, 16384) : mapSizeForTolerance(body, params.tol);
  render(body, params, mapGridFor(lo, hi, size, params.tol));
}

DepthMaps::DepthMaps(const TriMesh& body, const CollisionParams& params, const MapGrid& grid) {
  render(body, params, grid);
}

DepthMaps::DepthMaps(const TriMesh& body, const CollisionParams& params, const MapGrid& grid,
                     const MatrixX3d& vertexVelocity) {
  render(body, params, grid, &vertexVelocity);
}

void DepthMaps::render(const TriMesh& body, const CollisionParams& params, const MapGrid& grid,
                       const MatrixX3d* vertexVelocity) {
  const auto t0 = std::chrono::steady_clock::now();
  tol_ = params.tol;
  boundingBox(body, lo_, hi_);
  map_size_ = grid.map_size;
  pixel_ = grid.pixel;
  inv_pixel_ = 1.0 / pixel_;
  width_ = grid.width;
  height_ = grid.height;
  x0_ = grid.x0;
  y0_ = grid.y0;

  const std::size_t N = static_cast<std::size_t>(width_) * static_cast<std::size_t>(height_);
  // Memory is the main cost of a build (first touch of fresh pages), so there are no scratch
  // per-pixel buffers: a pixel is covered iff front > -inf, and during pass 1 the normal maps
  // (not initialized) hold the id of the winning face in their first float.
  front_.assign(N, -kInf);
  back_.assign(N, kInf);
  front_n_.resize(N);
  back_n_.resize(N);
  const bool velocity = vertexVelocity && vertexVelocity->rows() == body.V.rows();
  front_v_.assign(velocity ? N : 0, Eigen::Vector3f::Zero());
  back_v_.assign(velocity ? N : 0, Eigen::Vector3f::Zero());
  MapBuffers maps{width_, height_, front_, back_, front_n_, back_n_, front_v_, back_v_};
  VelocitySource vs;
  if (velocity) vs = {vertexVelocity, x0_, y0_, pixel_};

  std::vector<NormalField> fields;  // only for rasterized faces
  rasterize(body, x0_, y0_, inv_pixel_, maps, fields);
  covered_ = fillNormals(body, fields, tol_, maps, vs);
  ring_ = fillRing(maps);

  build_seconds_ = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

Eigen::Vector3d collisionResponse(const Eigen::Vector3d& v, const Eigen::Vector3d& n, double friction,
                                  double reflection) {
  const double vn_len = v.dot(n);
  const Eigen::Vector3d vn = vn_len * n;
  const Eigen::Vector3d vt = v - vn;
  if (vn_len < 0) return friction * vt - reflection * vn;
  return friction * vt + vn;
}

TriMesh viewMesh(MapView v, const TriMesh& body) {
  TriMesh t;
  t.F = body.F;
  t.V.resize(body.V.rows(), 3);
  for (Eigen::Index i = 0; i < body.V.rows(); ++i) t.V.row(i) = viewPoint(v, body.V.row(i).transpose()).transpose();
  return t;
}

}  // namespace virtual_tryon
