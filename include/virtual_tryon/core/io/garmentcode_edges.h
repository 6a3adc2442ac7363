// The edge curves of GarmentCode's pattern specification (Korosteleva and Sorkine-Hornung 2023,
// pygarment/pattern/core.py and meshgen/boxmeshgen.py): a straight line, a quadratic or cubic
// Bezier curve, or a circular arc, each between a panel's two outline vertices, in the panel's
// own 2D frame (y up).
#pragma once

#include "virtual_tryon/core/drape/pattern.h"

#include <Eigen/Core>

namespace virtual_tryon {

// One panel edge from `start` to `end` (panel units).
// Quadratic / cubic: `control` holds one / two control points in absolute panel coordinates.
// GarmentCode writes them relative to the edge (curvature_coords: relative): x along the edge from
// its start (0) to its end (1), y to its left, both scaled by the edge vector: the absolute point
// is start + x (end - start) + y perp(end - start) with perp(d) = (-d.y, d.x) (its rel_to_abs_2d);
// garmentCodeRelativeToAbsolute does that.
// Circle: an SVG-style arc (SVG 1.1 sec. F.6.5, as svgpathtools draws it in GarmentCode's mesher)
// of `radius`, the larger of the two arcs when `large_arc`, and on the right of the edge's direction
// (seen in the y-up panel frame) when `right` (the SVG sweep flag). A radius shorter than half the
// chord is scaled up to it (as SVG does), which gives a half circle.
struct GarmentCodeEdge {
  enum class Type { Line, Quadratic, Cubic, Circle };
  Type type = Type::Line;
  Eigen::Vector2d start = Eigen::Vector2d::Zero(), end = Eigen::Vector2d::Zero();
  Eigen::Vector2d control[2] = {Eigen::Vector2d::Zero(), Eigen::Vector2d::Zero()};
  double radius = 0;
  bool large_arc = false, right = false;
};

Eigen::Vector2d garmentCodeRelativeToAbsolute(const Eigen::Vector2d& start, const Eigen::Vector2d& end,
                                              const Eigen::Vector2d& relative);

// The point at curve parameter t in [0, 1] (Bezier parameter; for an arc, the angle fraction,
// which is also the arc-length fraction).
Eigen::Vector2d edgePoint(const GarmentCodeEdge& edge, double t);

// Length of the curve (Gauss-Legendre quadrature on 16 pieces for the Bezier curves: relative
// error below 1e-9 on any curve GarmentCode writes; exact for lines and arcs).
double edgeLength(const GarmentCodeEdge& edge);

// `segments` + 1 points along the curve at equal arc-length steps, start first and end last
// (as GarmentCode's mesher places its edge vertices). segments >= 1.
MatrixX2d sampleEdge(const GarmentCodeEdge& edge, int segments);

}  // namespace virtual_tryon
