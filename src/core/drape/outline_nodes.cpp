#include "core/drape/outline_nodes.h"

#include "core/drape/boundary_band.h"
#include "core/drape/pattern_text.h"

#include <algorithm>
#include <cmath>
#include <map>

namespace virtual_tryon {
namespace outline_nodes {

namespace {

using boundary_band::Vec2;

// Of two node fractions that the two sides of a seam ask for, closer than this (times the spacing,
// along the longer side), one is kept: two nodes so close would make a sliver.
constexpr double kMergeFraction = 0.3;

// Arc-length positions along a panel's counter-clockwise outline, from vertex 0.
struct Perimeter {
  const MatrixX2d* P = nullptr;
  std::vector<double> at;  // at[i]: position of vertex i; at[n]: the whole perimeter
  explicit Perimeter(const MatrixX2d& outline) : P(&outline) {
    const Eigen::Index n = outline.rows();
    at.assign(static_cast<std::size_t>(n) + 1, 0.0);
    for (Eigen::Index i = 0; i < n; ++i) at[i + 1] = at[i] + (outline.row((i + 1) % n) - outline.row(i)).norm();
  }
  double length() const { return at.back(); }
  double wrap(double s) const {
    const double L = length();
    s = std::fmod(s, L);
    return s < 0 ? s + L : s;
  }
  // The outline from position s0 to s1 going counter-clockwise (s1 > s0, may pass s = L).
  std::vector<Vec2> between(double s0, double s1) const {
    const Eigen::Index n = P->rows();
    std::vector<Vec2> pl{point(s0)};
    for (int turn = 0; turn < 2; ++turn)
      for (Eigen::Index i = 0; i < n; ++i) {
        const double s = at[i] + turn * length();
        if (s > s0 + 1e-12 && s < s1 - 1e-12) pl.push_back(P->row(i).transpose());
      }
    pl.push_back(point(s1));
    return pl;
  }
  Vec2 point(double s) const {
    s = wrap(s);
    const Eigen::Index n = P->rows();
    Eigen::Index i = static_cast<Eigen::Index>(std::upper_bound(at.begin(), at.end(), s) - at.begin()) - 1;
    i = std::clamp<Eigen::Index>(i, 0, n - 1);
    const double seg = at[i + 1] - at[i];
    const double t = seg > 0 ? (s - at[i]) / seg : 0.0;
    return ((1 - t) * P->row(i) + t * P->row((i + 1) % n)).transpose();
  }
};

// A stretch as positions along its panel's perimeter: start, end and direction of its walk.
struct StretchSpan {
  double start = 0, length = 0;
  int direction = 1;  // +1: counter-clockwise (increasing position), -1: clockwise
  double positionAt(const Perimeter& per, double f) const { return per.wrap(start + direction * f * length); }
  std::vector<Vec2> polyline(const Perimeter& per) const {
    if (direction > 0) return per.between(start, start + length);
    std::vector<Vec2> pl = per.between(start - length, start);
    std::reverse(pl.begin(), pl.end());
    return pl;
  }
};

StretchSpan spanOf(const Pattern& pattern, const Perimeter& per, const OutlineStretch& s) {
  const std::vector<int> walk = stretchVertices(pattern, s);
  const int n = static_cast<int>(pattern.panels[static_cast<std::size_t>(s.panel)].outline.rows());
  StretchSpan span;
  span.start = per.at[static_cast<std::size_t>(s.from)];
  span.direction = walk.size() >= 2 && walk[1] == (walk[0] + 1) % n ? 1 : -1;
  span.length = stretchLength(pattern, s);
  return span;
}

// Positions requested on one panel, each with the key of the node it becomes.
struct Requests {
  std::vector<double> pos;
  std::vector<std::pair<double, double>> covered;  // sewn spans [s0, s0 + len] (counter-clockwise)
};

// The index of position s in a panel's sorted unique node positions.
int indexOf(const std::vector<double>& sorted, double s, double L) {
  auto it = std::lower_bound(sorted.begin(), sorted.end(), s - 1e-9 * L);
  if (it == sorted.end() || std::abs(*it - s) > 1e-9 * L) {
    if (!sorted.empty() && std::abs(sorted.front() - (s - L)) <= 1e-9 * L) return 0;
    if (!sorted.empty() && std::abs(sorted.back() - (s + L)) <= 1e-9 * L) return static_cast<int>(sorted.size()) - 1;
    return -1;
  }
  return static_cast<int>(it - sorted.begin());
}

bool coveredBy(const Requests& r, double s0, double s1, double L) {
  const double mid = s1 > s0 ? 0.5 * (s0 + s1) : std::fmod(0.5 * (s0 + s1 + L), L);
  for (const auto& c : r.covered) {
    double d = mid - c.first;
    d = std::fmod(d, L);
    if (d < 0) d += L;
    if (d > 1e-12 && d < c.second - 1e-12) return true;
  }
  return false;
}

// Sorted fractions (0 and 1 included) with every one closer than `gap` to the last kept one
// dropped (the end, 1, is kept and its near neighbour dropped instead).
std::vector<double> mergeClose(const std::vector<double>& f, double gap) {
  std::vector<double> out{f.front()};
  for (std::size_t i = 1; i < f.size(); ++i) {
    if (f[i] - out.back() >= gap) {
      out.push_back(f[i]);
    } else if (i + 1 == f.size()) {
      if (out.size() > 1) out.back() = f[i];
      else out.push_back(f[i]);
    }
  }
  return out;
}

}  // namespace

bool sampleOutlines(const Pattern& pattern, double spacing, double tolerance, OutlineSampling& out,
                    std::string& error) {
  const std::size_t np = pattern.panels.size();
  std::vector<Perimeter> per;
  for (const auto& panel : pattern.panels) per.emplace_back(panel.outline);
  std::vector<Requests> req(np);
  // Seams: the same fractions on both sides.
  std::vector<std::vector<std::pair<double, double>>> seamPositions(pattern.seams.size());
  for (std::size_t k = 0; k < pattern.seams.size(); ++k) {
    const PatternSeam& seam = pattern.seams[k];
    const StretchSpan a = spanOf(pattern, per[seam.a.panel], seam.a), b = spanOf(pattern, per[seam.b.panel], seam.b);
    if (!(a.length > 0) || !(b.length > 0)) {
      error = "seam " + std::to_string(k) + ": a stretch of zero length";
      return false;
    }
    std::vector<double> f = boundary_band::requiredFractions(a.polyline(per[seam.a.panel]), tolerance);
    const std::vector<double> fb = boundary_band::requiredFractions(b.polyline(per[seam.b.panel]), tolerance);
    f.insert(f.end(), fb.begin(), fb.end());
    std::sort(f.begin(), f.end());
    f = mergeClose(f, kMergeFraction * spacing / std::max(a.length, b.length));
    f = boundary_band::subdivideFractions(f, std::max(a.length, b.length), spacing);
    for (double x : f) {
      const double sa = a.positionAt(per[seam.a.panel], x), sb = b.positionAt(per[seam.b.panel], x);
      req[seam.a.panel].pos.push_back(sa);
      req[seam.b.panel].pos.push_back(sb);
      seamPositions[k].push_back({sa, sb});
    }
    req[seam.a.panel].covered.push_back({a.direction > 0 ? a.start : per[seam.a.panel].wrap(a.start - a.length), a.length});
    req[seam.b.panel].covered.push_back({b.direction > 0 ? b.start : per[seam.b.panel].wrap(b.start - b.length), b.length});
  }
  // Each panel: its requested positions, then the unsewn gaps filled on their own.
  out.loops.assign(np, PanelLoop());
  std::vector<std::vector<double>> sorted(np);
  for (std::size_t p = 0; p < np; ++p) {
    const double L = per[p].length();
    std::vector<double> s = req[p].pos;
    if (s.empty()) s.push_back(0.0);
    for (double& x : s) x = per[p].wrap(x);
    std::sort(s.begin(), s.end());
    s.erase(std::unique(s.begin(), s.end(), [&](double x, double y) { return std::abs(x - y) <= 1e-9 * L; }), s.end());
    if (s.size() > 1 && std::abs(s.back() - L - s.front()) <= 1e-9 * L) s.pop_back();
    std::vector<double> all;
    for (std::size_t i = 0; i < s.size(); ++i) {
      const double s0 = s[i], s1 = i + 1 < s.size() ? s[i + 1] : s[0] + L;
      all.push_back(s0);
      if (s.size() > 1 && coveredBy(req[p], s0, s1, L)) continue;
      const std::vector<Vec2> pl = per[p].between(s0, s1);
      const double len = boundary_band::polylineLength(pl);
      const std::vector<double> f =
          boundary_band::subdivideFractions(boundary_band::requiredFractions(pl, tolerance), len, spacing);
      for (std::size_t j = 1; j + 1 < f.size(); ++j) all.push_back(per[p].wrap(s0 + f[j] * len));
    }
    std::sort(all.begin(), all.end());
    sorted[p] = all;
    for (double x : all) out.loops[p].uv.push_back(per[p].point(x));
  }
  out.seam_pairs.assign(pattern.seams.size(), {});
  for (std::size_t k = 0; k < pattern.seams.size(); ++k) {
    const PatternSeam& seam = pattern.seams[k];
    for (const auto& pr : seamPositions[k]) {
      const int ia = indexOf(sorted[seam.a.panel], pr.first, per[seam.a.panel].length());
      const int ib = indexOf(sorted[seam.b.panel], pr.second, per[seam.b.panel].length());
      if (ia < 0 || ib < 0) {
        error = "seam " + std::to_string(k) + ": internal error placing its nodes";
        return false;
      }
      out.seam_pairs[k].push_back({ia, ib});
    }
  }
  return true;
}

}  // namespace outline_nodes
}  // namespace virtual_tryon
