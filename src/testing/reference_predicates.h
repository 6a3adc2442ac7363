// The referee's predicates, shared by reference_check.cpp (brute force) and reference_bvh.cpp (its
// own AABB trees), so that both count with exactly the same tests. No FCL, nothing of the
// resolver's detector. Internal to the core library.
#pragma once

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>

namespace virtual_tryon {
namespace reference_predicates {

// Moller-Trumbore: does the segment o + t dir, eps < t < 1 - eps, meet triangle (a, b, c)
// (closed: edges and corners count)? `tOut` receives t when the supporting line meets it.
inline bool mtHit(const Eigen::Vector3d& o, const Eigen::Vector3d& dir, const Eigen::Vector3d& a,
           const Eigen::Vector3d& b, const Eigen::Vector3d& c, double eps, double* tOut = nullptr) {
  const Eigen::Vector3d e1 = b - a, e2 = c - a;
  const Eigen::Vector3d p = dir.cross(e2);
  const double det = e1.dot(p);
  if (std::abs(det) < 1e-300) return false;
  const double inv = 1.0 / det;
  const Eigen::Vector3d s = o - a;
  const double u = s.dot(p) * inv;
  if (u < 0 || u > 1) return false;
  const Eigen::Vector3d q = s.cross(e1);
  const double v = dir.dot(q) * inv;
  if (v < 0 || u + v > 1) return false;
  const double t = e2.dot(q) * inv;
  if (tOut) *tOut = t;
  return t > eps && t < 1 - eps;
}

// Euclidean distance from p to the closed triangle (a, b, c).
inline double pointTriangleDistance(const Eigen::Vector3d& p, const Eigen::Vector3d& a,
                             const Eigen::Vector3d& b, const Eigen::Vector3d& c) {
  // Projection if inside, else the nearest of the three edges.
  const Eigen::Vector3d n = (b - a).cross(c - a);
  const double nn = n.squaredNorm();
  if (nn > 0) {
    const Eigen::Vector3d q = p - n * (n.dot(p - a) / nn);
    const double w0 = (b - q).cross(c - q).dot(n), w1 = (c - q).cross(a - q).dot(n),
                 w2 = (a - q).cross(b - q).dot(n);
    if (w0 >= 0 && w1 >= 0 && w2 >= 0) return (p - q).norm();
  }
  auto seg = [&](const Eigen::Vector3d& u, const Eigen::Vector3d& v) {
    const Eigen::Vector3d d = v - u;
    const double t = d.squaredNorm() > 0 ? std::clamp((p - u).dot(d) / d.squaredNorm(), 0.0, 1.0) : 0.0;
    return (p - (u + t * d)).norm();
  };
  return std::min({seg(a, b), seg(b, c), seg(c, a)});
}

// The inside test: a point in the body's bounding box [lo, hi] is inside when at least two of
// three segments from it, along these directions (off every axis and every simple diagonal) and
// of this length (well past the box), cross the body an odd number of times.
inline const Eigen::Vector3d kInsideRayDirections[3] = {Eigen::Vector3d(0.4367, 0.8021, 0.4073).normalized(),
                                                        Eigen::Vector3d(-0.8812, 0.1732, -0.4397).normalized(),
                                                        Eigen::Vector3d(0.2113, -0.5557, 0.8041).normalized()};
inline double insideRayLength(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi) {
  return 3.0 * (hi - lo).norm() + 1.0;
}

}  // namespace reference_predicates
}  // namespace virtual_tryon
