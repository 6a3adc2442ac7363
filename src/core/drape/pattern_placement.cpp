// A pattern's placement moved onto the body that is being dressed (see the header's rule).
#include "virtual_tryon/core/drape/pattern_placement.h"

#include "virtual_tryon/core/geometry/point_queries.h"

#include <algorithm>
#include <cmath>
#include <vector>
#include <cstdio>
#include <limits>

namespace virtual_tryon {

BodyPlacement placementOnBody(const MatrixX3d& bodyV, const BodyPlacementParams& params) {
  BodyPlacement out;
  if (bodyV.rows() == 0) return out;
  const Eigen::Vector3d lo = bodyV.colwise().minCoeff().transpose(), hi = bodyV.colwise().maxCoeff().transpose();
  out.floor = lo.y();
  out.body_height = hi.y() - lo.y();
  const double xCentre = 0.5 * (lo.x() + hi.x());
  const double sliceY = lo.y() + params.hip_height * out.body_height;
  double zLo = std::numeric_limits<double>::infinity(), zHi = -zLo;
  for (Eigen::Index i = 0; i < bodyV.rows(); ++i) {
    if (std::abs(bodyV(i, 1) - sliceY) > params.slice_half_height) continue;
    if (std::abs(bodyV(i, 0) - xCentre) > params.torso_half_width) continue;
    zLo = std::min(zLo, bodyV(i, 2));
    zHi = std::max(zHi, bodyV(i, 2));
  }
  const double zCentre = zLo <= zHi ? 0.5 * (zLo + zHi) : 0.5 * (lo.z() + hi.z());
  out.torso_centre = Eigen::Vector3d(xCentre, sliceY, zCentre);
  out.scale = params.scale_to_height && params.source_height > 0 ? out.body_height / params.source_height : 1.0;
  out.offset = Eigen::Vector3d(xCentre, out.floor, zCentre);
  char line[256];
  std::snprintf(line, sizeof line,
                "floor y=0 -> %.3f, torso centre at hip height (%.3f m) x=%.3f z=%.3f, scale %.3f (body %.3f m)",
                out.floor, sliceY, xCentre, zCentre, out.scale, out.body_height);
  out.rule = line;
  return out;
}

void applyPlacement(const BodyPlacement& placement, Pattern& pattern) {
  for (PatternPanel& panel : pattern.panels) {
    Eigen::Vector3d t = panel.placement.pose.translation();
    panel.placement.pose.translation() = placement.scale * t + placement.offset;
  }
}

namespace {

// The 3D point at arc-length fraction f of a stretch (placed).
Eigen::Vector3d stretchPoint(const Pattern& pattern, const OutlineStretch& s, double f) {
  const std::vector<int> idx = stretchVertices(pattern, s);
  const PatternPanel& panel = pattern.panels[static_cast<std::size_t>(s.panel)];
  std::vector<double> cum(idx.size(), 0.0);
  for (std::size_t i = 1; i < idx.size(); ++i)
    cum[i] = cum[i - 1] + (panel.outline.row(idx[i]) - panel.outline.row(idx[i - 1])).norm();
  const double target = f * cum.back();
  std::size_t i = 1;
  while (i + 1 < idx.size() && cum[i] < target) ++i;
  const double len = cum[i] - cum[i - 1];
  const double t = len > 0 ? (target - cum[i - 1]) / len : 0.0;
  const Eigen::Vector2d uv = ((1 - t) * panel.outline.row(idx[i - 1]) + t * panel.outline.row(idx[i])).transpose();
  return panel.placement.place(uv);
}

bool lineBlocked(const Body& body, const Eigen::Vector3d& a, const Eigen::Vector3d& b, const SeamLiftParams& p) {
  const int n = std::max(1, static_cast<int>(std::ceil((b - a).norm() / p.step)));
  for (int k = 1; k < n; ++k) {
    const Eigen::Vector3d x = a + (b - a) * (double(k) / n);
    if (closestPointOnBody(body, x).distance < p.clearance || pointInsideBody(body, x)) return true;
  }
  return false;
}

}  // namespace

SeamLift seamLift(const Body& body, const Pattern& pattern, const SeamLiftParams& params) {
  SeamLift out;
  if (!body.closed() || !(params.step > 0)) return out;
  struct Line {
    Eigen::Vector3d a, b;
  };
  std::vector<Line> lines;
  for (const PatternSeam& seam : pattern.seams) {
    if (stretchVertices(pattern, seam.a).size() < 2 || stretchVertices(pattern, seam.b).size() < 2) continue;
    for (int k = 0; k < params.fractions; ++k) {
      const double f = (k + 0.5) / params.fractions;
      const Line l{stretchPoint(pattern, seam.a, f), stretchPoint(pattern, seam.b, f)};
      if ((l.b - l.a).norm() >= params.min_length) lines.push_back(l);
    }
  }
  out.lines = static_cast<int>(lines.size());
  const int steps = static_cast<int>(std::floor(params.max_lift / params.step + 1e-9));
  auto blockedAt = [&](int s) {
    const Eigen::Vector3d up(0, s * params.step, 0);
    int blocked = 0;
    for (const Line& l : lines)
      if (lineBlocked(body, l.a + up, l.b + up, params)) ++blocked;
    return blocked;
  };
  int best = -1, bestStep = 0;
  for (int s = 0; s <= steps; ++s) {
    const int blocked = blockedAt(s);
    if (s == 0) out.blocked_before = blocked;
    if (best < 0 || blocked < best) {
      best = blocked;
      bestStep = s;
    }
    if (blocked == 0) break;
  }
  if (bestStep == 0 && best == out.blocked_before && best > 0) return out;  // lifting does not help
  const int s = std::min(steps, bestStep + std::max(0, params.margin_steps));
  out.lift = s * params.step;
  out.blocked_after = s == bestStep ? best : blockedAt(s);
  return out;
}

BodyPlacement placePatternOnBody(const Body& body, Pattern& pattern, const BodyPlacementParams& params) {
  BodyPlacement placement = placementOnBody(body.mesh().V, params);
  applyPlacement(placement, pattern);
  if (!params.lift_seams) return placement;
  placement.lift = seamLift(body, pattern, params.lift);
  if (placement.lift.lift > 0) {
    BodyPlacement up;
    up.offset = Eigen::Vector3d(0, placement.lift.lift, 0);
    applyPlacement(up, pattern);
    placement.offset.y() += placement.lift.lift;
  }
  char line[160];
  std::snprintf(line, sizeof line, "; lifted %.3f m so that seams close over the body (blocked seam lines %d -> %d of %d)",
                placement.lift.lift, placement.lift.blocked_before, placement.lift.blocked_after, placement.lift.lines);
  placement.rule += line;
  return placement;
}

}  // namespace virtual_tryon
