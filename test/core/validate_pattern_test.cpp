// validatePattern: what makes a panel or a seam unusable, each named in its message.
#include "pattern_helpers.h"
#include "virtual_tryon/core/drape/pattern.h"

#include <gtest/gtest.h>

#include <cmath>

using namespace virtual_tryon;
using namespace virtual_tryon_test;

TEST(ValidatePattern, PanelProblems) {
  Pattern g;
  g.name = "dress";
  EXPECT_EQ(validatePattern(g), "pattern 'dress' has no panels");
  g.panels.push_back(rectPanel("front", 0, 0, 1, 1));
  EXPECT_EQ(validatePattern(g), "");
  g.panels.push_back(PatternPanel{"bow", outlineOf({{0, 0}, {1, 1}, {1, 0}, {0, 1}}), PanelPlacement()});
  EXPECT_EQ(validatePattern(g),
            "panel 'bow' (index 1): outline is self-intersecting: edge 0 (points 0-1) meets edge 2 (points 2-3)");
  // Touching counts: a vertex on a non-adjacent edge.
  g.panels[1].outline = outlineOf({{0, 0}, {2, 0}, {2, 2}, {1, 0}, {0, 2}});
  EXPECT_EQ(validatePattern(g),
            "panel 'bow' (index 1): outline is self-intersecting: edge 0 (points 0-1) meets edge 2 (points 2-3)");
  g.panels[1].outline = outlineOf({{0, 0}, {1, 0}});
  EXPECT_EQ(validatePattern(g), "panel 'bow' (index 1): outline has 2 points, needs at least 3");
  g.panels[1].outline = outlineOf({{0, 0}, {1, 0}, {NAN, 1}});
  EXPECT_EQ(validatePattern(g), "panel 'bow' (index 1): outline point 2 is not finite (nan, 1)");
  g.panels[1].outline = outlineOf({{0, 0}, {1, 0}, {2, 0}});
  EXPECT_EQ(validatePattern(g), "panel 'bow' (index 1): outline has zero area");
  g.panels[1].outline = outlineOf({{0, 0}, {1, 0}, {1, 0}, {0, 1}});
  EXPECT_EQ(validatePattern(g), "panel 'bow' (index 1): outline points 1 and 2 coincide (1, 0)");
  // Clockwise is fine (normalizePattern reverses it).
  g.panels[1].outline = outlineOf({{0, 0}, {0, 1}, {1, 1}, {1, 0}});
  EXPECT_EQ(validatePattern(g), "");

  g.panels[1].placement.wrap_radius = -0.1;
  EXPECT_EQ(validatePattern(g), "panel 'bow' (index 1): placement wrap_radius must be finite and >= 0 (0: flat), got -0.1");
  g.panels[1].placement.wrap_radius = INFINITY;
  EXPECT_EQ(validatePattern(g), "panel 'bow' (index 1): placement wrap_radius must be finite and >= 0 (0: flat), got inf");
  g.panels[1].placement.wrap_radius = 0;
  g.panels[1].placement.pose.translation().x() = NAN;
  EXPECT_EQ(validatePattern(g), "panel 'bow' (index 1): placement pose is not finite");
  g.panels[1].placement.pose = Eigen::Isometry3d::Identity();
  g.panels[1].placement.pose.linear() *= 2;
  EXPECT_EQ(validatePattern(g),
            "panel 'bow' (index 1): placement rotation is not a proper rotation (orthonormal, determinant +1)");
}

TEST(ValidatePattern, SeamProblems) {
  Pattern g = tube(0.2, 0.5);
  ASSERT_EQ(validatePattern(g), "");
  g.seams[1].b.panel = 2;
  EXPECT_EQ(validatePattern(g), "seam 1: b names panel 2, but the pattern has 2 panels (indices 0..1)");
  g.seams[1].b.panel = -1;
  EXPECT_EQ(validatePattern(g), "seam 1: b names panel -1, but the pattern has 2 panels (indices 0..1)");
  g = tube(0.2, 0.5);
  g.seams[0].a.to = 4;
  EXPECT_EQ(validatePattern(g),
            "seam 0: a.to = 4 is out of range for panel 'front' (index 0) with 4 outline points (0..3)");
  g = tube(0.2, 0.5);
  g.seams[0].b.from = 3;
  EXPECT_EQ(validatePattern(g), "seam 0: b has from == to (3); a stretch needs two distinct outline points");
  g = tube(0.2, 0.5);
  g.seams[0].b = st(1, 0, 2);
  EXPECT_EQ(validatePattern(g),
            "seam 0: b (panel 'back' (index 1), 0 -> 2) goes exactly half-way round the 4-point outline, so its "
            "direction is ambiguous; split the seam in two");
  g = tube(0.2, 0.5);
  g.seams[0].b = st(1, 2, 3);  // the waist edge, 0.628 m, against a 0.5 m side: ratio 1.257, fine
  EXPECT_EQ(validatePattern(g), "");
  g.panels[1].outline(2, 1) = g.panels[1].outline(3, 1) = 0.2;  // b's sides now 0.2 m
  g.seams[0].b = st(1, 0, 3);
  EXPECT_EQ(validatePattern(g),
            "seam 0: stretch lengths differ too much: a (panel 'front' (index 0), 1 -> 2) is 0.5 m, b (panel "
            "'back' (index 1), 0 -> 3) is 0.2 m; ratio 2.5 > 1.5");
  EXPECT_EQ(validatePattern(g, 3.0), "");
}
