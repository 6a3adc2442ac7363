// GarmentCode's edge curves: points, lengths, equal arc-length samples.
#include "virtual_tryon/core/io/garmentcode_edges.h"

#include <algorithm>
#include <cmath>
#include <vector>

namespace virtual_tryon {

namespace {

constexpr double kPi = 3.14159265358979323846;

// 5-point Gauss-Legendre nodes and weights on [-1, 1].
constexpr double kGaussNodes[5] = {0.0, -0.5384693101056831, 0.5384693101056831, -0.9061798459386640,
                                   0.9061798459386640};
constexpr double kGaussWeights[5] = {0.5688888888888889, 0.4786286704993665, 0.4786286704993665,
                                     0.2369268850561891, 0.2369268850561891};

struct Arc {
  Eigen::Vector2d centre;
  double radius = 0, theta0 = 0, sweep = 0;  // radians; sweep > 0 counter-clockwise
};

double angleBetween(const Eigen::Vector2d& u, const Eigen::Vector2d& v) {
  return std::atan2(u.x() * v.y() - u.y() * v.x(), u.dot(v));
}

// SVG 1.1 F.6.5 (rx = ry, no rotation), with F.6.6's radius scaling.
Arc arcOf(const GarmentCodeEdge& e) {
  Arc arc;
  const Eigen::Vector2d half = 0.5 * (e.start - e.end);  // (x1', y1')
  const double d2 = half.squaredNorm();
  double r = std::abs(e.radius);
  if (d2 <= 0) {
    arc.centre = e.start;
    arc.radius = r;
    return arc;
  }
  if (r * r < d2) r = std::sqrt(d2);
  double k = std::sqrt(std::max(0.0, (r * r - d2) / d2));
  if (e.large_arc == e.right) k = -k;
  const Eigen::Vector2d cPrime = k * Eigen::Vector2d(half.y(), -half.x());
  arc.centre = cPrime + 0.5 * (e.start + e.end);
  arc.radius = r;
  const Eigen::Vector2d u = (half - cPrime) / r, v = (-half - cPrime) / r;
  arc.theta0 = std::atan2(u.y(), u.x());
  double sweep = angleBetween(u, v);
  // The sweep flag (`right`): set, the angle grows (counter-clockwise in the y-up panel frame,
  // which puts the arc on the right of start -> end); unset, it falls.
  if (!e.right && sweep > 0) sweep -= 2 * kPi;
  if (e.right && sweep < 0) sweep += 2 * kPi;
  arc.sweep = sweep;
  return arc;
}

Eigen::Vector2d bezierDerivative(const GarmentCodeEdge& e, double t) {
  const double s = 1 - t;
  if (e.type == GarmentCodeEdge::Type::Quadratic)
    return 2 * s * (e.control[0] - e.start) + 2 * t * (e.end - e.control[0]);
  return 3 * s * s * (e.control[0] - e.start) + 6 * s * t * (e.control[1] - e.control[0]) +
         3 * t * t * (e.end - e.control[1]);
}

double bezierLength(const GarmentCodeEdge& e, double t0, double t1) {
  const double mid = 0.5 * (t0 + t1), half = 0.5 * (t1 - t0);
  double sum = 0;
  for (int i = 0; i < 5; ++i) sum += kGaussWeights[i] * bezierDerivative(e, mid + half * kGaussNodes[i]).norm();
  return sum * half;
}

bool isBezier(const GarmentCodeEdge& e) {
  return e.type == GarmentCodeEdge::Type::Quadratic || e.type == GarmentCodeEdge::Type::Cubic;
}

}  // namespace

Eigen::Vector2d garmentCodeRelativeToAbsolute(const Eigen::Vector2d& start, const Eigen::Vector2d& end,
                                              const Eigen::Vector2d& relative) {
  const Eigen::Vector2d d = end - start;
  return start + relative.x() * d + relative.y() * Eigen::Vector2d(-d.y(), d.x());
}

Eigen::Vector2d edgePoint(const GarmentCodeEdge& e, double t) {
  const double s = 1 - t;
  switch (e.type) {
    case GarmentCodeEdge::Type::Line: return s * e.start + t * e.end;
    case GarmentCodeEdge::Type::Quadratic: return s * s * e.start + 2 * s * t * e.control[0] + t * t * e.end;
    case GarmentCodeEdge::Type::Cubic:
      return s * s * s * e.start + 3 * s * s * t * e.control[0] + 3 * s * t * t * e.control[1] + t * t * t * e.end;
    case GarmentCodeEdge::Type::Circle: {
      if (t <= 0) return e.start;
      if (t >= 1) return e.end;
      const Arc arc = arcOf(e);
      const double a = arc.theta0 + t * arc.sweep;
      return arc.centre + arc.radius * Eigen::Vector2d(std::cos(a), std::sin(a));
    }
  }
  return e.start;
}

double edgeLength(const GarmentCodeEdge& e) {
  if (e.type == GarmentCodeEdge::Type::Line) return (e.end - e.start).norm();
  if (e.type == GarmentCodeEdge::Type::Circle) {
    const Arc arc = arcOf(e);
    return arc.radius * std::abs(arc.sweep);
  }
  constexpr int kPieces = 16;
  double sum = 0;
  for (int i = 0; i < kPieces; ++i) sum += bezierLength(e, double(i) / kPieces, double(i + 1) / kPieces);
  return sum;
}

MatrixX2d sampleEdge(const GarmentCodeEdge& e, int segments) {
  segments = std::max(1, segments);
  MatrixX2d P(segments + 1, 2);
  if (!isBezier(e)) {  // lines and arcs: the parameter is the arc-length fraction
    for (int k = 0; k <= segments; ++k) P.row(k) = edgePoint(e, double(k) / segments).transpose();
  } else {
    // Cumulative length over a fine table, then each target found in its table interval by
    // bisection on the interval's own quadrature.
    constexpr int kTable = 256;
    std::vector<double> cumulative(kTable + 1, 0.0);
    for (int i = 0; i < kTable; ++i)
      cumulative[i + 1] = cumulative[i] + bezierLength(e, double(i) / kTable, double(i + 1) / kTable);
    const double total = cumulative[kTable];
    for (int k = 0; k <= segments; ++k) {
      const double target = total * k / segments;
      const int i = std::min<int>(kTable - 1, int(std::upper_bound(cumulative.begin(), cumulative.end(), target) -
                                                  cumulative.begin()) - 1);
      double lo = double(std::max(0, i)) / kTable, hi = double(std::max(0, i) + 1) / kTable;
      const double base = cumulative[std::max(0, i)], t0 = lo;
      for (int it = 0; it < 40; ++it) {
        const double mid = 0.5 * (lo + hi);
        (base + bezierLength(e, t0, mid) < target ? lo : hi) = mid;
      }
      P.row(k) = edgePoint(e, 0.5 * (lo + hi)).transpose();
    }
  }
  P.row(0) = e.start.transpose();
  P.row(segments) = e.end.transpose();
  return P;
}

}  // namespace virtual_tryon
