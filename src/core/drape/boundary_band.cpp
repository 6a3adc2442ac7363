#include "core/drape/boundary_band.h"

#include "core/geometry/polygon2d.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <numeric>
#include <set>
#include <unordered_map>
#include <utility>

namespace virtual_tryon {
namespace boundary_band {

namespace {

using polygon2d::orient;

std::vector<double> cumulative(const std::vector<Vec2>& pl) {
  std::vector<double> cum(pl.size(), 0.0);
  for (std::size_t i = 1; i < pl.size(); ++i) cum[i] = cum[i - 1] + (pl[i] - pl[i - 1]).norm();
  return cum;
}

void douglasPeucker(const std::vector<Vec2>& pl, std::size_t first, std::size_t last, double tol,
                    std::vector<std::size_t>& keep) {
  if (last <= first + 1) return;
  double worst = -1;
  std::size_t at = first;
  for (std::size_t i = first + 1; i < last; ++i) {
    const double d = polygon2d::distanceToSegment(pl[i], pl[first], pl[last]);
    if (d > worst) {
      worst = d;
      at = i;
    }
  }
  if (worst <= tol) return;
  keep.push_back(at);
  douglasPeucker(pl, first, at, tol, keep);
  douglasPeucker(pl, at, last, tol, keep);
}

}  // namespace

double polylineLength(const std::vector<Vec2>& polyline) {
  return polyline.size() < 2 ? 0.0 : cumulative(polyline).back();
}

std::vector<double> requiredFractions(const std::vector<Vec2>& polyline, double tolerance) {
  const std::vector<double> cum = cumulative(polyline);
  const double len = cum.empty() ? 0.0 : cum.back();
  std::vector<std::size_t> keep{0, polyline.size() - 1};
  douglasPeucker(polyline, 0, polyline.size() - 1, tolerance, keep);
  std::sort(keep.begin(), keep.end());
  std::vector<double> f;
  for (std::size_t i : keep) f.push_back(len > 0 ? cum[i] / len : 0.0);
  f.front() = 0;
  f.back() = 1;
  return f;
}

std::vector<double> subdivideFractions(const std::vector<double>& fractions, double length, double spacing) {
  std::vector<double> out{fractions.front()};
  for (std::size_t i = 1; i < fractions.size(); ++i) {
    const double gap = (fractions[i] - fractions[i - 1]) * length;
    const int pieces = std::max(1, static_cast<int>(std::ceil(gap / spacing - 1e-9)));
    for (int k = 1; k < pieces; ++k) out.push_back(fractions[i - 1] + (fractions[i] - fractions[i - 1]) * k / pieces);
    out.push_back(fractions[i]);
  }
  return out;
}

namespace {

// Proper crossing of segments ab and cd (touching at an end-point does not count).
bool properCross(const Vec2& a, const Vec2& b, const Vec2& c, const Vec2& d) {
  const double o1 = orient(a, b, c), o2 = orient(a, b, d), o3 = orient(c, d, a), o4 = orient(c, d, b);
  return ((o1 > 0 && o2 < 0) || (o1 < 0 && o2 > 0)) && ((o3 > 0 && o4 < 0) || (o3 < 0 && o4 > 0));
}

bool insideLoop(const std::vector<Vec2>& pts, const std::vector<int>& loop, const Vec2& p) {
  bool in = false;
  for (std::size_t i = 0, j = loop.size() - 1; i < loop.size(); j = i++) {
    const Vec2& a = pts[loop[i]];
    const Vec2& b = pts[loop[j]];
    if ((a.y() > p.y()) != (b.y() > p.y()) && p.x() < (b.x() - a.x()) * (p.y() - a.y()) / (b.y() - a.y()) + a.x())
      in = !in;
  }
  return in;
}

// Whether segment pq meets no edge of any loop (edges at p or q aside) and runs inside the band.
bool visible(const std::vector<Vec2>& pts, const std::vector<std::vector<int>>& loops, int p, int q) {
  for (const auto& loop : loops)
    for (std::size_t i = 0; i < loop.size(); ++i) {
      const int a = loop[i], b = loop[(i + 1) % loop.size()];
      if (a == p || a == q || b == p || b == q) continue;
      if (properCross(pts[p], pts[q], pts[a], pts[b])) return false;
      // A loop vertex on the segment blocks it too.
      if (polygon2d::distanceToSegment(pts[a], pts[p], pts[q]) < 1e-12) return false;
    }
  const Vec2 mid = 0.5 * (pts[p] + pts[q]);
  if (!insideLoop(pts, loops[0], mid)) return false;
  for (std::size_t h = 1; h < loops.size(); ++h)
    if (insideLoop(pts, loops[h], mid)) return false;
  return true;
}

// Merges every hole into the outer loop through a bridge to the nearest visible outer vertex
// (holes taken by their rightmost vertex, right to left). The bridge's two ends appear twice.
bool bridgeHoles(const std::vector<Vec2>& pts, std::vector<std::vector<int>> loops, std::vector<int>& merged) {
  std::vector<std::size_t> order(loops.size() - 1);
  std::iota(order.begin(), order.end(), 1);
  auto rightmost = [&](const std::vector<int>& l) {
    std::size_t best = 0;
    for (std::size_t i = 1; i < l.size(); ++i)
      if (pts[l[i]].x() > pts[l[best]].x()) best = i;
    return best;
  };
  std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
    return pts[loops[a][rightmost(loops[a])]].x() > pts[loops[b][rightmost(loops[b])]].x();
  });
  std::vector<std::vector<int>> current{loops[0]};
  for (std::size_t h : order) current.push_back(loops[h]);
  for (std::size_t k = 1; k < current.size(); ++k) {
    std::vector<int>& hole = current[k];
    std::vector<int>& outer = current[0];
    const std::size_t mi = rightmost(hole);
    const int m = hole[mi];
    std::vector<std::size_t> cand(outer.size());
    std::iota(cand.begin(), cand.end(), 0);
    std::sort(cand.begin(), cand.end(), [&](std::size_t a, std::size_t b) {
      return (pts[outer[a]] - pts[m]).squaredNorm() < (pts[outer[b]] - pts[m]).squaredNorm();
    });
    std::vector<std::vector<int>> others{outer};
    for (std::size_t j = k; j < current.size(); ++j) others.push_back(current[j]);
    std::size_t pick = outer.size();
    for (std::size_t c : cand)
      if (visible(pts, others, m, outer[c])) {
        pick = c;
        break;
      }
    if (pick == outer.size()) return false;
    std::vector<int> next(outer.begin(), outer.begin() + static_cast<long>(pick) + 1);
    for (std::size_t i = 0; i <= hole.size(); ++i) next.push_back(hole[(mi + i) % hole.size()]);
    next.insert(next.end(), outer.begin() + static_cast<long>(pick), outer.end());
    outer = next;
    hole.clear();
  }
  merged = current[0];
  return true;
}

// Ear clipping; the scan for the next ear starts where the last one was cut (quality comes from
// the Delaunay flips afterwards).
bool earClip(const std::vector<Vec2>& pts, std::vector<int> poly, std::vector<std::array<int, 3>>& tris) {
  std::size_t start = 0;
  while (poly.size() > 3) {
    const std::size_t n = poly.size();
    std::size_t found = n;
    for (std::size_t step = 0; step < n && found == n; ++step) {
      const std::size_t i = (start + step) % n;
      const int a = poly[(i + n - 1) % n], b = poly[i], c = poly[(i + 1) % n];
      if (orient(pts[a], pts[b], pts[c]) <= 0) continue;
      bool empty = true;
      for (std::size_t j = 0; j < n && empty; ++j) {
        const int q = poly[j];
        if (q == a || q == b || q == c) continue;
        if (orient(pts[a], pts[b], pts[q]) >= 0 && orient(pts[b], pts[c], pts[q]) >= 0 &&
            orient(pts[c], pts[a], pts[q]) >= 0)
          empty = false;
      }
      if (empty) found = i;
    }
    if (found == n) return false;
    tris.push_back({poly[(found + n - 1) % n], poly[found], poly[(found + 1) % n]});
    poly.erase(poly.begin() + static_cast<long>(found));
    start = found == 0 ? 0 : found - 1;
  }
  if (poly.size() == 3) {
    if (orient(pts[poly[0]], pts[poly[1]], pts[poly[2]]) <= 0) return false;
    tris.push_back({poly[0], poly[1], poly[2]});
  }
  return true;
}

// d strictly inside the circumcircle of the counter-clockwise triangle abc.
bool inCircle(const Vec2& a, const Vec2& b, const Vec2& c, const Vec2& d) {
  const Vec2 ad = a - d, bd = b - d, cd = c - d;
  const double det = ad.squaredNorm() * polygon2d::cross(bd, cd) - bd.squaredNorm() * polygon2d::cross(ad, cd) +
                     cd.squaredNorm() * polygon2d::cross(ad, bd);
  return det > 1e-18;
}

// Lawson flips of every edge that is not a loop edge, until the triangulation is
// constrained-Delaunay: a stack of edges to check, the triangles on each directed edge kept up to
// date as edges flip.
void delaunayFlips(const std::vector<Vec2>& pts, const std::set<std::pair<int, int>>& fixed,
                   std::vector<std::array<int, 3>>& tris) {
  auto dkey = [](int a, int b) { return (static_cast<long long>(a) << 32) | static_cast<unsigned>(b); };
  std::unordered_map<long long, int> on;  // directed edge a->b: the triangle that has it
  for (std::size_t t = 0; t < tris.size(); ++t)
    for (int k = 0; k < 3; ++k) on[dkey(tris[t][k], tris[t][(k + 1) % 3])] = static_cast<int>(t);
  std::vector<std::pair<int, int>> stack;
  for (std::size_t t = 0; t < tris.size(); ++t)
    for (int k = 0; k < 3; ++k) stack.push_back({tris[t][k], tris[t][(k + 1) % 3]});
  auto third = [](const std::array<int, 3>& t, int a, int b) {
    for (int k = 0; k < 3; ++k)
      if (t[k] != a && t[k] != b) return t[k];
    return -1;
  };
  std::size_t guard = 0;
  const std::size_t limit = 64 * tris.size() + 1000;
  while (!stack.empty() && ++guard < limit) {
    const int a = stack.back().first, b = stack.back().second;
    stack.pop_back();
    if (fixed.count({std::min(a, b), std::max(a, b)})) continue;
    const auto i0 = on.find(dkey(a, b)), i1 = on.find(dkey(b, a));
    if (i0 == on.end() || i1 == on.end()) continue;
    const int t0 = i0->second, t1 = i1->second;
    const int c = third(tris[t0], a, b), d = third(tris[t1], a, b);
    if (c < 0 || d < 0 || c == d) continue;
    if (!inCircle(pts[a], pts[b], pts[c], pts[d])) continue;
    if (orient(pts[a], pts[d], pts[c]) <= 0 || orient(pts[d], pts[b], pts[c]) <= 0) continue;
    for (int t : {t0, t1})
      for (int k = 0; k < 3; ++k) on.erase(dkey(tris[t][k], tris[t][(k + 1) % 3]));
    tris[t0] = {a, d, c};
    tris[t1] = {d, b, c};
    for (int t : {t0, t1})
      for (int k = 0; k < 3; ++k) on[dkey(tris[t][k], tris[t][(k + 1) % 3])] = t;
    stack.push_back({a, d});
    stack.push_back({d, b});
    stack.push_back({b, c});
    stack.push_back({c, a});
  }
}

}  // namespace

bool triangulateBand(const std::vector<Vec2>& points, const std::vector<std::vector<int>>& loops,
                     std::vector<std::array<int, 3>>& triangles) {
  triangles.clear();
  if (loops.empty() || loops[0].size() < 3) return false;
  std::vector<int> merged;
  if (!bridgeHoles(points, loops, merged)) return false;
  // A clipping that ends on three points in a line (a straight run of the outline) starts again
  // from another vertex.
  bool clipped = false;
  for (std::size_t attempt = 0; attempt < std::min<std::size_t>(merged.size(), 16) && !clipped; ++attempt) {
    triangles.clear();
    std::vector<int> rotated(merged.begin() + static_cast<long>(attempt * merged.size() / 16), merged.end());
    rotated.insert(rotated.end(), merged.begin(), merged.begin() + static_cast<long>(attempt * merged.size() / 16));
    clipped = earClip(points, rotated, triangles);
  }
  if (!clipped) return false;
  std::set<std::pair<int, int>> fixed;
  for (const auto& loop : loops)
    for (std::size_t i = 0; i < loop.size(); ++i) {
      const int a = loop[i], b = loop[(i + 1) % loop.size()];
      fixed.insert({std::min(a, b), std::max(a, b)});
    }
  delaunayFlips(points, fixed, triangles);
  return true;
}

}  // namespace boundary_band
}  // namespace virtual_tryon
