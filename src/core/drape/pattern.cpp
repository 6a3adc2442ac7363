// Garment patterns: panel placement, stretches, validation and normalisation.
// (Meshing: pattern_mesher.cpp; YAML: pattern_yaml.cpp.)
#include "virtual_tryon/core/drape/pattern.h"

#include "core/drape/pattern_text.h"
#include "core/geometry/polygon2d.h"

#include <algorithm>
#include <utility>
#include <cmath>
#include <sstream>

namespace virtual_tryon {

namespace {

using pattern_text::num;
using pattern_text::panelLabel;

// Edges walked going up in index order from `from` to `to` (wrapping), on an outline of n points.
int edgesUp(int n, const OutlineStretch& s) { return ((s.to - s.from) % n + n) % n; }

std::string panelProblem(const PatternPanel& panel) {
  using namespace polygon2d;
  const MatrixX2d& P = panel.outline;
  const Eigen::Index n = P.rows();
  if (n < 3) return "outline has " + std::to_string(n) + " point" + (n == 1 ? "" : "s") + ", needs at least 3";
  for (Eigen::Index i = 0; i < n; ++i)
    if (!P.row(i).allFinite())
      return "outline point " + std::to_string(i) + " is not finite (" + num(P(i, 0)) + ", " + num(P(i, 1)) + ")";
  for (Eigen::Index i = 0; i < n; ++i) {
    const Eigen::Index j = (i + 1) % n;
    if (P(i, 0) == P(j, 0) && P(i, 1) == P(j, 1))
      return "outline points " + std::to_string(i) + " and " + std::to_string(j) + " coincide (" +
             num(P(i, 0)) + ", " + num(P(i, 1)) + ")";
  }
  // Self-intersection: any two non-adjacent edges meeting (touching included). O(n^2).
  for (Eigen::Index i = 0; i < n; ++i)
    for (Eigen::Index j = i + 2; j < n; ++j) {
      if (i == 0 && j == n - 1) continue;  // adjacent through the wrap
      if (segmentsIntersect(point(P, i), point(P, (i + 1) % n), point(P, j), point(P, (j + 1) % n)))
        return "outline is self-intersecting: edge " + std::to_string(i) + " (points " + std::to_string(i) +
               "-" + std::to_string((i + 1) % n) + ") meets edge " + std::to_string(j) + " (points " +
               std::to_string(j) + "-" + std::to_string((j + 1) % n) + ")";
    }
  const Eigen::Vector2d lo = P.colwise().minCoeff().transpose(), hi = P.colwise().maxCoeff().transpose();
  const double scale = (hi - lo).norm();
  if (!(std::abs(signedArea(P)) > 1e-12 * scale * scale)) return "outline has zero area";

  const PanelPlacement& pl = panel.placement;
  if (!pl.pose.matrix().allFinite()) return "placement pose is not finite";
  const Eigen::Matrix3d R = pl.pose.linear();
  if ((R.transpose() * R - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff() > 1e-6 || R.determinant() < 0)
    return "placement rotation is not a proper rotation (orthonormal, determinant +1)";
  if (!std::isfinite(pl.wrap_radius) || pl.wrap_radius < 0)
    return "placement wrap_radius must be finite and >= 0 (0: flat), got " + num(pl.wrap_radius);
  return "";
}

}  // namespace

Eigen::Vector3d PanelPlacement::place(const Eigen::Vector2d& uv) const {
  if (wrap_radius > 0) {
    const double r = wrap_radius, a = uv.x() / r;
    return pose * Eigen::Vector3d(r * std::sin(a), uv.y(), r * std::cos(a));
  }
  return pose * Eigen::Vector3d(uv.x(), uv.y(), 0.0);
}

double outlineSignedArea(const MatrixX2d& outline) { return polygon2d::signedArea(outline); }

std::vector<int> stretchVertices(const Pattern& pattern, const OutlineStretch& s) {
  if (s.panel < 0 || s.panel >= static_cast<int>(pattern.panels.size())) return {};
  const int n = static_cast<int>(pattern.panels[static_cast<std::size_t>(s.panel)].outline.rows());
  if (n < 2 || s.from < 0 || s.from >= n || s.to < 0 || s.to >= n || s.from == s.to) return {};
  const int up = edgesUp(n, s), down = n - up;
  // The way round with fewer edges; a tie (refused by validatePattern) goes up.
  const int step = up <= down ? 1 : -1, count = std::min(up, down);
  std::vector<int> walk;
  walk.reserve(static_cast<std::size_t>(count) + 1);
  for (int k = 0, v = s.from; k <= count; ++k, v = ((v + step) % n + n) % n) walk.push_back(v);
  return walk;
}

int patternOpenings(const Pattern& pattern) {
  // Outline vertex (p, i) is id offset[p] + i; outline edge (p, i) runs from vertex i to i + 1.
  std::vector<int> offset(pattern.panels.size() + 1, 0);
  for (std::size_t p = 0; p < pattern.panels.size(); ++p)
    offset[p + 1] = offset[p] + static_cast<int>(pattern.panels[p].outline.rows());
  std::vector<int> parent(static_cast<std::size_t>(offset.back()));
  for (std::size_t i = 0; i < parent.size(); ++i) parent[i] = static_cast<int>(i);
  auto find = [&](int v) {
    while (parent[v] != v) v = parent[v] = parent[parent[v]];
    return v;
  };
  auto join = [&](int a, int b) { parent[find(a)] = find(b); };
  std::vector<char> sewn(parent.size(), 0);
  for (const PatternSeam& seam : pattern.seams) {
    for (const OutlineStretch* st : {&seam.a, &seam.b}) {
      const std::vector<int> walk = stretchVertices(pattern, *st);
      const int n = static_cast<int>(pattern.panels[static_cast<std::size_t>(st->panel)].outline.rows());
      for (std::size_t k = 0; k + 1 < walk.size(); ++k) {
        const int lo = (walk[k] + 1) % n == walk[k + 1] ? walk[k] : walk[k + 1];
        sewn[static_cast<std::size_t>(offset[st->panel] + lo)] = 1;
      }
    }
    if (stretchVertices(pattern, seam.a).empty() || stretchVertices(pattern, seam.b).empty()) continue;
    join(offset[seam.a.panel] + seam.a.from, offset[seam.b.panel] + seam.b.from);
    join(offset[seam.a.panel] + seam.a.to, offset[seam.b.panel] + seam.b.to);
  }
  // The free edges between the joined corners; each connected piece of them is one opening.
  std::vector<std::pair<int, int>> free;
  for (std::size_t p = 0; p < pattern.panels.size(); ++p) {
    const int n = offset[p + 1] - offset[p];
    for (int i = 0; i < n; ++i)
      if (!sewn[static_cast<std::size_t>(offset[p] + i)])
        free.push_back({find(offset[p] + i), find(offset[p] + (i + 1) % n)});
  }
  std::vector<int> piece(parent.size());
  for (std::size_t i = 0; i < piece.size(); ++i) piece[i] = static_cast<int>(i);
  auto top = [&](int v) {
    while (piece[v] != v) v = piece[v] = piece[piece[v]];
    return v;
  };
  for (const auto& e : free) piece[top(e.first)] = top(e.second);
  std::vector<char> counted(parent.size(), 0);
  int openings = 0;
  for (const auto& e : free) {
    const int r = top(e.first);
    if (!counted[static_cast<std::size_t>(r)]) {
      counted[static_cast<std::size_t>(r)] = 1;
      ++openings;
    }
  }
  return openings;
}

double stretchLength(const Pattern& pattern, const OutlineStretch& s) {
  const std::vector<int> walk = stretchVertices(pattern, s);
  if (walk.empty()) return 0;
  const MatrixX2d& P = pattern.panels[static_cast<std::size_t>(s.panel)].outline;
  double len = 0;
  for (std::size_t k = 1; k < walk.size(); ++k) len += (P.row(walk[k]) - P.row(walk[k - 1])).norm();
  return len;
}

std::string validatePattern(const Pattern& pattern, double maxLengthRatio) {
  if (pattern.panels.empty())
    return "pattern" + (pattern.name.empty() ? std::string() : " '" + pattern.name + "'") + " has no panels";
  if (pattern.panels.size() > kMaxPatternPanels)
    return "pattern has " + std::to_string(pattern.panels.size()) + " panels, more than the limit of " +
           std::to_string(kMaxPatternPanels);
  if (pattern.seams.size() > kMaxPatternSeams)
    return "pattern has " + std::to_string(pattern.seams.size()) + " seams, more than the limit of " +
           std::to_string(kMaxPatternSeams);
  std::size_t points = 0;
  for (std::size_t p = 0; p < pattern.panels.size(); ++p) {
    const std::size_t n = static_cast<std::size_t>(pattern.panels[p].outline.rows());
    if (n > kMaxOutlinePoints)
      return panelLabel(pattern, static_cast<int>(p)) + ": outline has " + std::to_string(n) +
             " points, more than the limit of " + std::to_string(kMaxOutlinePoints);
    points += n;
  }
  if (points > kMaxPatternOutlinePoints)
    return "pattern has " + std::to_string(points) + " outline points in all, more than the limit of " +
           std::to_string(kMaxPatternOutlinePoints);
  const int np = static_cast<int>(pattern.panels.size());
  for (int p = 0; p < np; ++p) {
    const std::string problem = panelProblem(pattern.panels[static_cast<std::size_t>(p)]);
    if (!problem.empty()) return panelLabel(pattern, p) + ": " + problem;
  }
  for (std::size_t k = 0; k < pattern.seams.size(); ++k) {
    const std::string seam = "seam " + std::to_string(k) + ": ";
    const PatternSeam& sm = pattern.seams[k];
    for (int side = 0; side < 2; ++side) {
      const OutlineStretch& s = side == 0 ? sm.a : sm.b;
      const std::string which = side == 0 ? "a" : "b";
      if (s.panel < 0 || s.panel >= np)
        return seam + which + " names panel " + std::to_string(s.panel) + ", but the pattern has " +
               std::to_string(np) + " panel" + (np == 1 ? "" : "s") + " (indices 0.." + std::to_string(np - 1) + ")";
      const int n = static_cast<int>(pattern.panels[static_cast<std::size_t>(s.panel)].outline.rows());
      for (const auto& [key, v] : {std::pair<const char*, int>{"from", s.from}, {"to", s.to}})
        if (v < 0 || v >= n)
          return seam + which + "." + key + " = " + std::to_string(v) + " is out of range for " +
                 panelLabel(pattern, s.panel) + " with " + std::to_string(n) + " outline points (0.." +
                 std::to_string(n - 1) + ")";
      if (s.from == s.to)
        return seam + which + " has from == to (" + std::to_string(s.from) +
               "); a stretch needs two distinct outline points";
      if (2 * edgesUp(n, s) == n)
        return seam + which + " (" + panelLabel(pattern, s.panel) + ", " + std::to_string(s.from) + " -> " +
               std::to_string(s.to) + ") goes exactly half-way round the " + std::to_string(n) +
               "-point outline, so its direction is ambiguous; split the seam in two";
    }
    const double la = stretchLength(pattern, sm.a), lb = stretchLength(pattern, sm.b);
    const double ratio = std::max(la, lb) / std::min(la, lb);
    if (!(ratio <= maxLengthRatio))
      return seam + "stretch lengths differ too much: a (" + panelLabel(pattern, sm.a.panel) + ", " +
             std::to_string(sm.a.from) + " -> " + std::to_string(sm.a.to) + ") is " + num(la) + " m, b (" +
             panelLabel(pattern, sm.b.panel) + ", " + std::to_string(sm.b.from) + " -> " +
             std::to_string(sm.b.to) + ") is " + num(lb) + " m; ratio " + num(ratio) + " > " + num(maxLengthRatio);
  }
  return "";
}

void normalizePattern(Pattern& pattern) {
  for (std::size_t p = 0; p < pattern.panels.size(); ++p) {
    MatrixX2d& P = pattern.panels[p].outline;
    if (P.rows() < 3 || !(outlineSignedArea(P) < 0)) continue;
    const int n = static_cast<int>(P.rows());
    P = P.colwise().reverse().eval();
    // Point i is now point n-1-i. A stretch keeps its points and its direction: its walk from
    // `from` to `to` the short way round becomes the walk from n-1-from to n-1-to the short way
    // round (same number of edges, now going the other way in index order).
    for (PatternSeam& s : pattern.seams)
      for (OutlineStretch* st : {&s.a, &s.b})
        if (st->panel == static_cast<int>(p) && st->from >= 0 && st->from < n && st->to >= 0 && st->to < n) {
          st->from = n - 1 - st->from;
          st->to = n - 1 - st->to;
        }
  }
}

}  // namespace virtual_tryon
