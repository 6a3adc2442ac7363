// Shared by the pattern suites (panel_placement, mesh_pattern, validate_pattern, stretch,
// normalize_pattern, pattern_yaml): small patterns built in code, and what to look at in a meshed
// ClothMesh.
#pragma once

#include "virtual_tryon/core/drape/pattern.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include <cstddef>
#include <initializer_list>
#include <string>
#include <utility>
#include <vector>

namespace virtual_tryon_test {

namespace vt = virtual_tryon;

inline constexpr double kPi = 3.14159265358979323846;

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
