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

// floor(a / kSub) and ceil(a / kSub) (kSub a power of two; >> of a negative int64 is an arithmetic
// shift on every compiler we target, and well defined from C++20).
inline std::int64_t floorSub(std::int64_t a) { return a >> kSubBits; }
inline std::int64_t ceilSub(std::int64_t a) { return -((-a) >> kSubBits); }

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

DepthMaps::DepthMaps(const TriMesh& body, const CollisionParams& params) {
  const auto t0 = std::chrono::steady_clock::now();
  tol_ = params.tol;
  boundingBox(body, lo_, hi_);
  map_size_ = params.map_size > 0 ? std::min(params.map_size, 16384) : mapSizeForTolerance(body, tol_);

  const double ex = hi_.x() - lo_.x(), ey = hi_.y() - lo_.y();
  const double extent = std::max(ex, ey);
  pixel_ = extent > 0 ? extent / map_size_ : (tol_ > 0 ? tol_ : 1e-3);
  inv_pixel_ = 1.0 / pixel_;
  // Same slack as mapSizeForTolerance: the longer side gets exactly map_size pixels.
  const int inner_w = std::max(1, static_cast<int>(std::ceil(ex / pixel_ - 1e-9)));
  const int inner_h = std::max(1, static_cast<int>(std::ceil(ey / pixel_ - 1e-9)));
  width_ = inner_w + 2;
  height_ = inner_h + 2;
  x0_ = lo_.x() - pixel_;
  y0_ = lo_.y() - pixel_;

  const std::size_t W = static_cast<std::size_t>(width_), H = static_cast<std::size_t>(height_);
  const std::size_t N = W * H;
  constexpr float kInf = std::numeric_limits<float>::infinity();
  constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();
  // Memory is the main cost of a build (first touch of fresh pages), so there are no scratch
  // per-pixel buffers: a pixel is covered iff front > -inf, and during pass 1 the normal maps
  // (not initialized) hold the id of the winning face in their first float.
  front_.assign(N, -kInf);
  back_.assign(N, kInf);
  front_n_.resize(N);
  back_n_.resize(N);
  auto setId = [](Eigen::Vector3f& slot, int id) { std::memcpy(slot.data(), &id, sizeof id); };
  auto getId = [](const Eigen::Vector3f& slot) {
    int id;
    std::memcpy(&id, slot.data(), sizeof id);
    return id;
  };

  // Vertices in fixed-point pixel coordinates (x right, y up).
  const Eigen::Index nv = body.V.rows();
  // (|values| < 16386 * 256 < 2^31; the products below are formed in 64 bits.)
  std::vector<std::int32_t> fx(static_cast<std::size_t>(nv)), fy(static_cast<std::size_t>(nv));
  const double scale = inv_pixel_ * kSub;
  for (Eigen::Index i = 0; i < nv; ++i) {
    // Rounded to nearest; the values are >= one pixel (the margin), so truncating u + 1/2 does it.
    fx[i] = static_cast<std::int32_t>((body.V(i, 0) - x0_) * scale + 0.5);
    fy[i] = static_cast<std::int32_t>((body.V(i, 1) - y0_) * scale + 0.5);
  }
  const MatrixX3d VN = vertexNormals(body);
  // Per rasterized face: the interpolated (unnormalized) vertex normal as an affine function of
  // the pixel indices, relative to the face's first pixel (X0, Y0), for pass 2.
  struct NormalField {
    float n0[3], dX[3], dY[3];
    int X0, Y0, face;
  };
  std::vector<NormalField> fields;  // only for rasterized faces; reserve touches no memory
  fields.reserve(static_cast<std::size_t>(body.F.rows()));

  // --- Pass 1: z-buffer both maps at once. ---
  for (Eigen::Index f = 0; f < body.F.rows(); ++f) {
    int ia = body.F(f, 0), ib = body.F(f, 1), ic = body.F(f, 2);
    const std::int64_t ax = fx[ia], ay = fy[ia];
    std::int64_t bx = fx[ib], by = fy[ib], cx = fx[ic], cy = fy[ic];
    // Pixel range whose centres (X kSub + kHalf) fall in the triangle's box; most triangles of a
    // fine mesh at a coarse map hold no centre at all and stop here.
    const std::int64_t X0 = std::max<std::int64_t>(0, ceilSub(std::min({ax, bx, cx}) - kHalf));
    const std::int64_t X1 = std::min<std::int64_t>(width_ - 1, floorSub(std::max({ax, bx, cx}) - kHalf));
    if (X0 > X1) continue;
    const std::int64_t Y0 = std::max<std::int64_t>(0, ceilSub(std::min({ay, by, cy}) - kHalf));
    const std::int64_t Y1 = std::min<std::int64_t>(height_ - 1, floorSub(std::max({ay, by, cy}) - kHalf));
    if (Y0 > Y1) continue;
    std::int64_t area = (bx - ax) * (cy - ay) - (by - ay) * (cx - ax);
    if (area == 0) continue;
    if (area < 0) {  // make it counter-clockwise in x-y
      std::swap(ib, ic);
      std::swap(bx, cx);
      std::swap(by, cy);
      area = -area;
    }

    // Edge function of edge p->q at s: (q - p) x (s - p), >= 0 on the left (inside), exact.
    // Fill rule: owned edges accept 0, the others need > 0, i.e. E - bias >= 0, bias 0 or 1.
    struct Edge {
      std::int64_t row, stepX, stepY, bias;
    };
    const std::int64_t sx0 = X0 * kSub + kHalf, sy0 = Y0 * kSub + kHalf;
    auto makeEdge = [&](std::int64_t px, std::int64_t py, std::int64_t qx, std::int64_t qy) {
      const std::int64_t dx = qx - px, dy = qy - py;
      const bool owned = dy < 0 || (dy == 0 && dx < 0);
      Edge e;
      e.bias = owned ? 0 : 1;
      e.row = dx * (sy0 - py) - dy * (sx0 - px) - e.bias;
      e.stepX = -dy * kSub;
      e.stepY = dx * kSub;
      return e;
    };
    Edge e0 = makeEdge(bx, by, cx, cy);  // area * barycentric weight of a
    Edge e1 = makeEdge(cx, cy, ax, ay);  // of b
    Edge e2 = makeEdge(ax, ay, bx, by);  // of c

    // Barycentric weights at (X0, Y0) and their steps; z and the normal are affine in them.
    const double inv_area = 1.0 / static_cast<double>(area);
    const double w0 = static_cast<double>(e0.row + e0.bias) * inv_area,
                 w1 = static_cast<double>(e1.row + e1.bias) * inv_area,
                 w2 = static_cast<double>(e2.row + e2.bias) * inv_area;
    const double gx0 = static_cast<double>(e0.stepX) * inv_area, gx1 = static_cast<double>(e1.stepX) * inv_area,
                 gx2 = static_cast<double>(e2.stepX) * inv_area;
    const double gy0 = static_cast<double>(e0.stepY) * inv_area, gy1 = static_cast<double>(e1.stepY) * inv_area,
                 gy2 = static_cast<double>(e2.stepY) * inv_area;
    const double za = body.V(ia, 2), zb = body.V(ib, 2), zc = body.V(ic, 2);
    double zrow = w0 * za + w1 * zb + w2 * zc;
    const double dzX = gx0 * za + gx1 * zb + gx2 * zc;
    const double dzY = gy0 * za + gy1 * zb + gy2 * zc;
    const int id = static_cast<int>(fields.size());  // what the maps store during pass 1
    fields.emplace_back();
    NormalField& nf = fields.back();
    nf.X0 = static_cast<int>(X0);
    nf.Y0 = static_cast<int>(Y0);
    nf.face = static_cast<int>(f);
    for (int k = 0; k < 3; ++k) {
      const double na = VN(ia, k), nb = VN(ib, k), nc = VN(ic, k);
      nf.n0[k] = static_cast<float>(w0 * na + w1 * nb + w2 * nc);
      nf.dX[k] = static_cast<float>(gx0 * na + gx1 * nb + gx2 * nc);
      nf.dY[k] = static_cast<float>(gy0 * na + gy1 * nb + gy2 * nc);
    }

    for (std::int64_t Y = Y0; Y <= Y1; ++Y) {
      std::int64_t E0 = e0.row, E1 = e1.row, E2 = e2.row;
      double z = zrow;
      std::size_t idx = static_cast<std::size_t>(Y) * W + static_cast<std::size_t>(X0);
      for (std::int64_t X = X0; X <= X1; ++X, ++idx) {
        if ((E0 | E1 | E2) >= 0) {
          const float zf = static_cast<float>(z);
          if (zf > front_[idx]) {
            front_[idx] = zf;
            setId(front_n_[idx], id);
          }
          if (zf < back_[idx]) {
            back_[idx] = zf;
            setId(back_n_[idx], id);
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

  // --- Pass 2: normals of the winning faces, tol. Empty pixels stay -inf / +inf for now. ---
  auto normalOf = [&](int id, int X, int Y) -> Eigen::Vector3f {
    const NormalField& nf = fields[static_cast<std::size_t>(id)];
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
  };
  const float ftol = static_cast<float>(tol_);
  for (int Y = 0; Y < height_; ++Y) {
    std::size_t i = static_cast<std::size_t>(Y) * W;
    for (int X = 0; X < width_; ++X, ++i) {
      if (!(front_[i] > -kInf)) continue;
      ++covered_;
      front_n_[i] = normalOf(getId(front_n_[i]), X, Y);
      back_n_[i] = normalOf(getId(back_n_[i]), X, Y);
      front_[i] += ftol;
      back_[i] -= ftol;
    }
  }

  // --- Pass 3: one silhouette ring (8-neighbourhood) from the covered pixels (front > -inf; the
  // ring is applied afterwards, so it does not seed itself). Empty pixels become NaN, which also
  // fails "> -inf". ---
  static const int kDX[8] = {1, -1, 0, 0, 1, 1, -1, -1};
  static const int kDY[8] = {0, 0, 1, -1, 1, -1, 1, -1};
  struct RingPixel {
    std::size_t i;
    int kf, kb;
  };
  std::vector<RingPixel> ring;
  for (int Y = 0; Y < height_; ++Y) {
    std::size_t i = static_cast<std::size_t>(Y) * W;
    for (int X = 0; X < width_; ++X, ++i) {
      if (front_[i] > -kInf) continue;  // covered
      if (X > 0 && Y > 0 && X + 1 < width_ && Y + 1 < height_) {
        // Fast rejection away from the silhouette (most empty pixels): no covered 8-neighbour.
        const float* up = &front_[i + W];
        const float* mid = &front_[i];
        const float* down = &front_[i - W];
        const bool any = (up[-1] > -kInf) | (up[0] > -kInf) | (up[1] > -kInf) | (mid[-1] > -kInf) |
                         (mid[1] > -kInf) | (down[-1] > -kInf) | (down[0] > -kInf) | (down[1] > -kInf);
        if (!any) {
          front_[i] = back_[i] = kNaN;
          front_n_[i].setZero();
          back_n_[i].setZero();
          continue;
        }
      }
      int kf = -1, kb = -1;
      float best_f = -kInf, best_b = kInf;
      for (int k = 0; k < 8; ++k) {
        const int nx = X + kDX[k], ny = Y + kDY[k];
        if (nx < 0 || ny < 0 || nx >= width_ || ny >= height_) continue;
        const std::size_t j = static_cast<std::size_t>(ny) * W + static_cast<std::size_t>(nx);
        if (!(front_[j] > -kInf)) continue;
        if (front_[j] > best_f) {
          best_f = front_[j];
          kf = k;
        }
        if (back_[j] < best_b) {
          best_b = back_[j];
          kb = k;
        }
      }
      if (kf >= 0) {
        ring.push_back({i, kf, kb});
      } else {
        front_[i] = back_[i] = kNaN;
        front_n_[i].setZero();
        back_n_[i].setZero();
      }
    }
  }
  auto ringNormal = [&](std::size_t i, int k, const std::vector<Eigen::Vector3f>& normals) {
    const std::size_t j = i + static_cast<std::size_t>(static_cast<std::ptrdiff_t>(kDY[k]) * width_ + kDX[k]);
    // Outward: from the neighbour to this pixel, i.e. minus the offset to the neighbour.
    const Eigen::Vector3f o = Eigen::Vector3f(static_cast<float>(-kDX[k]), static_cast<float>(-kDY[k]), 0.f).normalized();
    const Eigen::Vector3f s = normals[j] + o;
    const float len = s.norm();
    return len > 1e-6f ? Eigen::Vector3f(s / len) : o;
  };
  for (const RingPixel& r : ring) {
    const std::size_t jf = r.i + static_cast<std::size_t>(static_cast<std::ptrdiff_t>(kDY[r.kf]) * width_ + kDX[r.kf]);
    const std::size_t jb = r.i + static_cast<std::size_t>(static_cast<std::ptrdiff_t>(kDY[r.kb]) * width_ + kDX[r.kb]);
    front_[r.i] = front_[jf];
    back_[r.i] = back_[jb];
    front_n_[r.i] = ringNormal(r.i, r.kf, front_n_);
    back_n_[r.i] = ringNormal(r.i, r.kb, back_n_);
  }
  ring_ = ring.size();

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

}  // namespace virtual_tryon
