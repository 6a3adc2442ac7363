// Small 2D polygon predicates shared by the pattern code (private to src/core).
#pragma once

#include <Eigen/Core>

#include <algorithm>
#include <cmath>

namespace virtual_tryon {
namespace polygon2d {

using Vec2 = Eigen::Vector2d;

template <typename Outline>
inline Vec2 point(const Outline& outline, Eigen::Index i) {
  return Vec2(outline(i, 0), outline(i, 1));
}

inline double cross(const Vec2& a, const Vec2& b) { return a.x() * b.y() - a.y() * b.x(); }

// > 0 when a, b, c turn counter-clockwise.
inline double orient(const Vec2& a, const Vec2& b, const Vec2& c) { return cross(b - a, c - a); }

inline int sign(double x) { return (x > 0) - (x < 0); }

// p is known to be collinear with a-b: is it within the segment's box?
inline bool withinBox(const Vec2& p, const Vec2& a, const Vec2& b) {
  return p.x() >= std::min(a.x(), b.x()) && p.x() <= std::max(a.x(), b.x()) &&
         p.y() >= std::min(a.y(), b.y()) && p.y() <= std::max(a.y(), b.y());
}

// Closed segments a-b and c-d share a point (touching and collinear overlap count).
inline bool segmentsIntersect(const Vec2& a, const Vec2& b, const Vec2& c, const Vec2& d) {
  const int o1 = sign(orient(a, b, c)), o2 = sign(orient(a, b, d));
  const int o3 = sign(orient(c, d, a)), o4 = sign(orient(c, d, b));
  if (o1 * o2 < 0 && o3 * o4 < 0) return true;  // proper crossing
  // Otherwise they meet only where an end point lies on the other segment.
  if (o1 == 0 && withinBox(c, a, b)) return true;
  if (o2 == 0 && withinBox(d, a, b)) return true;
  if (o3 == 0 && withinBox(a, c, d)) return true;
  if (o4 == 0 && withinBox(b, c, d)) return true;
  return false;
}

// Segments a-b and c-d cross properly: each one's end points lie strictly on opposite sides of the
// other's line (by more than `tol` in distance). Touching does not count.
inline bool segmentsCross(const Vec2& a, const Vec2& b, const Vec2& c, const Vec2& d, double tol) {
  const double lab = (b - a).norm(), lcd = (d - c).norm();
  if (lab <= 0 || lcd <= 0) return false;
  const double o1 = orient(a, b, c) / lab, o2 = orient(a, b, d) / lab;
  const double o3 = orient(c, d, a) / lcd, o4 = orient(c, d, b) / lcd;
  return ((o1 > tol && o2 < -tol) || (o1 < -tol && o2 > tol)) &&
         ((o3 > tol && o4 < -tol) || (o3 < -tol && o4 > tol));
}

inline double distanceToSegment(const Vec2& p, const Vec2& a, const Vec2& b) {
  const Vec2 ab = b - a;
  const double len2 = ab.squaredNorm();
  double t = len2 > 0 ? (p - a).dot(ab) / len2 : 0.0;
  t = std::clamp(t, 0.0, 1.0);
  return (p - (a + t * ab)).norm();
}

template <typename Outline>
inline double signedArea(const Outline& outline) {
  const Eigen::Index n = outline.rows();
  double twice = 0;
  for (Eigen::Index i = 0; i < n; ++i) {
    const Eigen::Index j = (i + 1) % n;
    twice += outline(i, 0) * outline(j, 1) - outline(j, 0) * outline(i, 1);
  }
  return 0.5 * twice;
}

template <typename Outline>
inline double distanceToOutline(const Vec2& p, const Outline& outline) {
  const Eigen::Index n = outline.rows();
  double best = INFINITY;
  for (Eigen::Index i = 0; i < n; ++i)
    best = std::min(best, distanceToSegment(p, point(outline, i), point(outline, (i + 1) % n)));
  return best;
}

// Crossing-number test (either orientation). Points exactly on the boundary may go either way:
// callers that care test distanceToOutline first.
template <typename Outline>
inline bool strictlyInside(const Vec2& p, const Outline& outline) {
  const Eigen::Index n = outline.rows();
  bool in = false;
  for (Eigen::Index i = 0, j = n - 1; i < n; j = i++) {
    const double yi = outline(i, 1), yj = outline(j, 1);
    if ((yi > p.y()) != (yj > p.y())) {
      const double x = outline(j, 0) + (p.y() - yj) / (yi - yj) * (outline(i, 0) - outline(j, 0));
      if (p.x() < x) in = !in;
    }
  }
  return in;
}

// Inside, or within `tol` of the boundary.
template <typename Outline>
inline bool insideOrOn(const Vec2& p, const Outline& outline, double tol) {
  return distanceToOutline(p, outline) <= tol || strictlyInside(p, outline);
}

// Convex (every turn the same way or straight)?
template <typename Outline>
inline bool isConvex(const Outline& outline) {
  const Eigen::Index n = outline.rows();
  bool pos = false, neg = false;
  for (Eigen::Index i = 0; i < n; ++i) {
    const double o = orient(point(outline, i), point(outline, (i + 1) % n), point(outline, (i + 2) % n));
    pos = pos || o > 0;
    neg = neg || o < 0;
  }
  return !(pos && neg);
}

}  // namespace polygon2d
}  // namespace virtual_tryon
