// Internal to the core: the boundary band of a meshed panel (pattern_mesher.cpp). The panel keeps
// the paper's regular grid inside; along the outline a loop of nodes lies on the outline itself,
// and the band between that loop and the grid's edge is triangulated.
//   - sampleStretch fractions: where along a polyline nodes go so that every chord stays within a
//     tolerance of the polyline and no chord is longer than the spacing;
//   - triangulateBand: a polygon with holes (the outline loop, the grid's edge loops) into
//     triangles, by ear clipping over bridged holes, then made constrained-Delaunay by edge flips
//     (the loops' edges stay).
#pragma once

#include <Eigen/Core>

#include <array>
#include <vector>

namespace virtual_tryon {
namespace boundary_band {

using Vec2 = Eigen::Vector2d;

// Arc-length fractions (0 and 1 included, increasing) of the polyline's vertices that a chain of
// chords must keep so that every polyline vertex lies within `tolerance` of its chord
// (Douglas-Peucker).
std::vector<double> requiredFractions(const std::vector<Vec2>& polyline, double tolerance);

// `fractions` (sorted, 0 and 1 included) with points added evenly into every gap longer than
// `spacing` along a line of `length`.
std::vector<double> subdivideFractions(const std::vector<double>& fractions, double length, double spacing);

double polylineLength(const std::vector<Vec2>& polyline);

// Triangulates the polygon whose outer boundary is loops[0] (counter-clockwise) and whose holes
// are loops[1..] (clockwise), each a list of indices into `points`. Triangles are counter-
// clockwise. Returns false when a step finds no valid triangle (a loop that crosses another).
bool triangulateBand(const std::vector<Vec2>& points, const std::vector<std::vector<int>>& loops,
                     std::vector<std::array<int, 3>>& triangles);

}  // namespace boundary_band
}  // namespace virtual_tryon
