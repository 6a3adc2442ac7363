// Shared by the pattern suites (panel_placement, mesh_pattern, validate_pattern, stretch,
// normalize_pattern, pattern_yaml) and the drape suites (drape, worn_garment): small patterns built
// in code, the shipped procedural patterns, and what to look at in a meshed ClothMesh.
#pragma once

#include "virtual_tryon/core/drape/pattern.h"
#include "virtual_tryon/core/geometry/mesh.h"
#include "virtual_tryon/core/io/pattern_yaml.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <functional>
#include <map>
#include <set>
#include <tuple>
#include <initializer_list>
#include <string>
#include <utility>
#include <vector>

namespace virtual_tryon_test {

namespace vt = virtual_tryon;

inline constexpr double kPi = 3.14159265358979323846;

// A shipped pattern of config/patterns/procedural/ (a failure of the calling test when it does not
// read).
inline vt::Pattern proceduralPattern(const std::string& name) {
  vt::Pattern p;
  std::string err;
  EXPECT_TRUE(vt::readPatternYaml(std::string(VIRTUAL_TRYON_SOURCE_DIR) + "/config/patterns/procedural/" + name, p, err))
      << err;
  return p;
}

inline vt::MatrixX2d outlineOf(std::initializer_list<std::pair<double, double>> pts) {
  vt::MatrixX2d P(static_cast<Eigen::Index>(pts.size()), 2);
  Eigen::Index i = 0;
  for (const auto& p : pts) {
    P(i, 0) = p.first;
    P(i, 1) = p.second;
    ++i;
  }
  return P;
}

inline vt::PatternPanel rectPanel(const std::string& name, double x0, double y0, double x1, double y1) {
  vt::PatternPanel p;
  p.name = name;
  p.outline = outlineOf({{x0, y0}, {x1, y0}, {x1, y1}, {x0, y1}});
  return p;
}

inline vt::OutlineStretch st(int panel, int from, int to) {
  vt::OutlineStretch s;
  s.panel = panel;
  s.from = from;
  s.to = to;
  return s;
}

inline vt::PatternSeam seamOf(vt::OutlineStretch a, vt::OutlineStretch b) {
  vt::PatternSeam s;
  s.a = a;
  s.b = b;
  return s;
}

// Two rectangles w x h, each wrapped half a turn round a cylinder of radius r (w = pi r), the back
// one turned half a turn about +y; sewn along both sides, hem to hem.
inline vt::Pattern tube(double r, double h) {
  vt::Pattern g;
  g.name = "tube";
  const double w = kPi * r;
  g.panels.push_back(rectPanel("front", -w / 2, 0, w / 2, h));
  g.panels.push_back(rectPanel("back", -w / 2, 0, w / 2, h));
  for (vt::PatternPanel& p : g.panels) p.placement.wrap_radius = r;
  g.panels[1].placement.pose.linear() = Eigen::AngleAxisd(kPi, Eigen::Vector3d::UnitY()).toRotationMatrix();
  g.seams.push_back(seamOf(st(0, 1, 2), st(1, 0, 3)));  // front right (+x) with back left, hem up
  g.seams.push_back(seamOf(st(0, 0, 3), st(1, 1, 2)));  // front left (-x) with back right, hem up
  return g;
}

inline Eigen::Vector3d triNormal(const vt::ClothMesh& c, Eigen::Index t) {
  const Eigen::Vector3d a = c.X.row(c.F(t, 0)).transpose(), b = c.X.row(c.F(t, 1)).transpose(),
                        d = c.X.row(c.F(t, 2)).transpose();
  return (b - a).cross(d - a).normalized();
}

inline std::vector<vt::SeamPair> pairsOfSeam(const vt::ClothMesh& c, int seam) {
  std::vector<vt::SeamPair> out;
  for (const vt::SeamPair& p : c.seam_pairs)
    if (p.seam == seam) out.push_back(p);
  return out;
}

// What every meshed pattern must be (issue "A sewn garment is one piece"):
//   - triangles counter-clockwise in uv, covering each panel's outline exactly (areas add up);
//   - no sliver: every triangle's smallest angle at least `minAngleDeg`;
//   - each panel's edge one loop of nodes on its outline, running round it in order (no teeth),
//     and every outline point within 1% of the spacing of that loop;
//   - springs at their uv rest length, none twice, none of zero length;
//   - seams edge to edge: consecutive pairs of a seam are neighbours along both panels' loops,
//     and once every pair is merged the cloth's boundary loops are the pattern's openings.
// `pattern` is the one meshed (normalised or not).
inline void expectConformingMesh(const vt::Pattern& input, const vt::ClothMesh& c, double spacing,
                                 double minAngleDeg = 15) {
  vt::Pattern pattern = input;
  vt::normalizePattern(pattern);
  auto uv = [&](int n) { return Eigen::Vector2d(c.UV(n, 0), c.UV(n, 1)); };
  auto cross = [](const Eigen::Vector2d& a, const Eigen::Vector2d& b) { return a.x() * b.y() - a.y() * b.x(); };
  std::vector<double> area(pattern.panels.size(), 0.0);
  double worstAngle = 180;
  for (Eigen::Index t = 0; t < c.F.rows(); ++t) {
    const Eigen::Vector2d a = uv(c.F(t, 0)), b = uv(c.F(t, 1)), d = uv(c.F(t, 2));
    const double twice = cross(b - a, d - a);
    ASSERT_GT(twice, 0) << "triangle " << t << " is not counter-clockwise in uv";
    area[static_cast<std::size_t>(c.panel[static_cast<std::size_t>(c.F(t, 0))])] += 0.5 * twice;
    for (const auto& [p, q, r] : {std::tuple{a, b, d}, std::tuple{b, d, a}, std::tuple{d, a, b}}) {
      const Eigen::Vector2d u = q - p, v = r - p;
      worstAngle = std::min(worstAngle, std::atan2(std::abs(cross(u, v)), u.dot(v)) * 180 / kPi);
    }
  }
  EXPECT_GE(worstAngle, minAngleDeg) << "a sliver triangle";
  for (std::size_t p = 0; p < pattern.panels.size(); ++p)
    EXPECT_NEAR(area[p], vt::outlineSignedArea(pattern.panels[p].outline), 1e-9 * (1 + area[p])) << "panel " << p;
  // Boundary edges per panel: directed as their triangle runs (counter-clockwise round the panel).
  std::map<std::pair<int, int>, int> uses;
  for (Eigen::Index t = 0; t < c.F.rows(); ++t)
    for (int k = 0; k < 3; ++k) ++uses[{std::min(c.F(t, k), c.F(t, (k + 1) % 3)), std::max(c.F(t, k), c.F(t, (k + 1) % 3))}];
  std::map<int, int> next;
  for (Eigen::Index t = 0; t < c.F.rows(); ++t)
    for (int k = 0; k < 3; ++k) {
      const int a = c.F(t, k), b = c.F(t, (k + 1) % 3);
      if (uses[{std::min(a, b), std::max(a, b)}] == 1) next[a] = b;
    }
  std::vector<int> loopsPerPanel(pattern.panels.size(), 0);
  std::set<int> seen;
  for (const auto& start : next) {
    if (seen.count(start.first)) continue;
    const int p = c.panel[static_cast<std::size_t>(start.first)];
    ++loopsPerPanel[static_cast<std::size_t>(p)];
    const vt::MatrixX2d& P = pattern.panels[static_cast<std::size_t>(p)].outline;
    // Arc position of a point on the outline, and distance to it.
    std::vector<double> at(static_cast<std::size_t>(P.rows()) + 1, 0.0);
    for (Eigen::Index i = 0; i < P.rows(); ++i) at[i + 1] = at[i] + (P.row((i + 1) % P.rows()) - P.row(i)).norm();
    auto locate = [&](const Eigen::Vector2d& q, double& dist) {
      double best = 1e9, s = 0;
      for (Eigen::Index i = 0; i < P.rows(); ++i) {
        const Eigen::Vector2d a = P.row(i).transpose(), b = P.row((i + 1) % P.rows()).transpose();
        const double t = std::clamp((q - a).dot(b - a) / (b - a).squaredNorm(), 0.0, 1.0);
        const double d = (q - (a + t * (b - a))).norm();
        if (d < best) best = d, s = at[i] + t * (b - a).norm();
      }
      dist = best;
      return s;
    };
    std::vector<int> loop;
    for (int v = start.first; !seen.count(v); v = next.at(v)) {
      seen.insert(v);
      loop.push_back(v);
      ASSERT_TRUE(next.count(next.at(v))) << "the boundary does not close";
    }
    double turns = 0, d = 0;
    for (std::size_t i = 0; i < loop.size(); ++i) {
      const double s0 = locate(uv(loop[i]), d);
      EXPECT_LT(d, 1e-9) << "boundary node " << loop[i] << " is off the outline";
      const double s1 = locate(uv(loop[(i + 1) % loop.size()]), d);
      double step = s1 - s0;
      if (step < -0.5 * at.back()) step += at.back();
      EXPECT_GT(step, 0) << "boundary nodes " << loop[i] << " -> " << loop[(i + 1) % loop.size()] << " run backwards (a tooth)";
      turns += step;
    }
    EXPECT_NEAR(turns, at.back(), 1e-6) << "panel " << p << ": the boundary goes round its outline once";
    // Every outline point within 1% of the spacing of the boundary polyline.
    for (Eigen::Index i = 0; i < P.rows(); ++i) {
      double best = 1e9;
      for (std::size_t k = 0; k < loop.size(); ++k) {
        const Eigen::Vector2d a = uv(loop[k]), b = uv(loop[(k + 1) % loop.size()]), q = P.row(i).transpose();
        const double t = std::clamp((q - a).dot(b - a) / (b - a).squaredNorm(), 0.0, 1.0);
        best = std::min(best, (q - (a + t * (b - a))).norm());
      }
      EXPECT_LE(best, 0.01 * spacing) << "panel " << p << " outline point " << i;
    }
  }
  for (std::size_t p = 0; p < pattern.panels.size(); ++p) EXPECT_EQ(loopsPerPanel[p], 1) << "panel " << p;
  std::set<std::pair<int, int>> springs;
  for (const vt::Spring& s : c.springs) {
    EXPECT_GT(s.rest, 0);
    EXPECT_NEAR(s.rest, (uv(s.a) - uv(s.b)).norm(), 1e-12);
    EXPECT_TRUE(springs.insert({std::min(s.a, s.b), std::max(s.a, s.b)}).second) << "spring " << s.a << "-" << s.b << " twice";
  }
  // Seams edge to edge, then merged: the openings are all that is left open.
  auto boundaryEdge = [&](int a, int b) { return uses.count({std::min(a, b), std::max(a, b)}) && uses[{std::min(a, b), std::max(a, b)}] == 1; };
  for (std::size_t k = 0; k < pattern.seams.size(); ++k) {
    const std::vector<vt::SeamPair> pairs = pairsOfSeam(c, static_cast<int>(k));
    for (std::size_t i = 0; i + 1 < pairs.size(); ++i) {
      EXPECT_TRUE(boundaryEdge(pairs[i].a, pairs[i + 1].a)) << "seam " << k << " pair " << i << ": side a skips a node";
      EXPECT_TRUE(boundaryEdge(pairs[i].b, pairs[i + 1].b)) << "seam " << k << " pair " << i << ": side b skips a node";
    }
  }
  std::vector<int> parent(static_cast<std::size_t>(c.X.rows()));
  for (std::size_t i = 0; i < parent.size(); ++i) parent[i] = static_cast<int>(i);
  std::function<int(int)> find = [&](int v) { return parent[v] == v ? v : parent[v] = find(parent[v]); };
  for (const vt::SeamPair& s : c.seam_pairs) parent[find(s.a)] = find(s.b);
  vt::TriMesh sewn;
  sewn.V = c.X;
  sewn.F = c.F;
  for (Eigen::Index t = 0; t < sewn.F.rows(); ++t)
    for (int k = 0; k < 3; ++k) sewn.F(t, k) = find(sewn.F(t, k));
  EXPECT_EQ(vt::boundaryLoops(sewn), static_cast<std::size_t>(vt::patternOpenings(pattern)));
}

inline void expectSamePattern(const vt::Pattern& a, const vt::Pattern& b, double tol) {
  EXPECT_EQ(a.name, b.name);
  ASSERT_EQ(a.panels.size(), b.panels.size());
  for (std::size_t i = 0; i < a.panels.size(); ++i) {
    const vt::PatternPanel &p = a.panels[i], &q = b.panels[i];
    EXPECT_EQ(p.name, q.name);
    ASSERT_EQ(p.outline.rows(), q.outline.rows());
    EXPECT_LE((p.outline - q.outline).cwiseAbs().maxCoeff(), tol) << p.name;
    EXPECT_LE((p.placement.pose.matrix() - q.placement.pose.matrix()).cwiseAbs().maxCoeff(), tol) << p.name;
    EXPECT_NEAR(p.placement.wrap_radius, q.placement.wrap_radius, tol) << p.name;
  }
  ASSERT_EQ(a.seams.size(), b.seams.size());
  for (std::size_t k = 0; k < a.seams.size(); ++k)
    for (auto [s, t] : {std::pair{a.seams[k].a, b.seams[k].a}, std::pair{a.seams[k].b, b.seams[k].b}}) {
      EXPECT_EQ(s.panel, t.panel) << "seam " << k;
      EXPECT_EQ(s.from, t.from) << "seam " << k;
      EXPECT_EQ(s.to, t.to) << "seam " << k;
    }
}

}  // namespace virtual_tryon_test
