// normalizePattern: clockwise outlines reversed, their seams renumbered onto the same points.
#include "pattern_helpers.h"
#include "virtual_tryon/core/drape/pattern.h"

#include <gtest/gtest.h>

#include <cstddef>
#include <string>
#include <utility>

using namespace virtual_tryon;
using namespace virtual_tryon_test;

TEST(NormalizePattern, ReversesClockwiseOutlinesAndKeepsSeams) {
  // The tube with the back panel's outline listed clockwise.
  Pattern g = tube(0.2, 0.5);
  const MatrixX2d ccw = g.panels[1].outline;
  g.panels[1].outline = ccw.colwise().reverse().eval();  // points 0..3 are now old 3..0
  // Same seams in the new numbering: old i is now 3 - i.
  g.seams[0].b = st(1, 3, 0);  // old 0 -> 3
  g.seams[1].b = st(1, 2, 1);  // old 1 -> 2
  ASSERT_LT(outlineSignedArea(g.panels[1].outline), 0);
  ASSERT_EQ(validatePattern(g), "");
  ClothMesh before;
  std::string error;
  ASSERT_TRUE(meshPattern(g, 0.05, before, error)) << error;

  Pattern n = g;
  normalizePattern(n);
  EXPECT_GT(outlineSignedArea(n.panels[0].outline), 0);
  EXPECT_GT(outlineSignedArea(n.panels[1].outline), 0);
  EXPECT_EQ(n.panels[0].outline, g.panels[0].outline);  // already CCW: untouched
  EXPECT_EQ(n.panels[1].outline, ccw);
  // Stretches on the reversed panel are renumbered i -> n-1-i and keep their points and direction.
  EXPECT_EQ(n.seams[0].b.from, 0);
  EXPECT_EQ(n.seams[0].b.to, 3);
  EXPECT_EQ(n.seams[1].b.from, 1);
  EXPECT_EQ(n.seams[1].b.to, 2);
  EXPECT_EQ(n.seams[0].a.from, 1);  // panel 0's stretches unchanged
  for (std::size_t k = 0; k < g.seams.size(); ++k) {
    const auto wg = stretchVertices(g, g.seams[k].b), wn = stretchVertices(n, n.seams[k].b);
    ASSERT_EQ(wg.size(), wn.size());
    for (std::size_t i = 0; i < wg.size(); ++i)
      EXPECT_EQ(g.panels[1].outline.row(wg[i]), n.panels[1].outline.row(wn[i]));
  }
  // Meshing gives the same cloth and the same seam pairs.
  ClothMesh after;
  ASSERT_TRUE(meshPattern(n, 0.05, after, error)) << error;
  EXPECT_EQ(before.X, after.X);
  ASSERT_EQ(before.seam_pairs.size(), after.seam_pairs.size());
  for (std::size_t k = 0; k < before.seam_pairs.size(); ++k) {
    EXPECT_EQ(before.seam_pairs[k].a, after.seam_pairs[k].a);
    EXPECT_EQ(before.seam_pairs[k].b, after.seam_pairs[k].b);
  }
  // Idempotent.
  Pattern twice = n;
  normalizePattern(twice);
  expectSamePattern(twice, n, 0);
}

TEST(NormalizePattern, SamePanelSeamAndLongerWalks) {
  // A 6-point clockwise panel sewn to itself; both stretches are renumbered.
  Pattern g;
  g.panels.push_back(PatternPanel{"p", outlineOf({{0, 0}, {0, 1}, {1, 2}, {2, 1}, {2, 0}, {1, -1}}), PanelPlacement()});
  g.seams.push_back(seamOf(st(0, 5, 1), st(0, 2, 4)));
  ASSERT_LT(outlineSignedArea(g.panels[0].outline), 0);
  Pattern n = g;
  normalizePattern(n);
  EXPECT_EQ(n.seams[0].a.from, 0);
  EXPECT_EQ(n.seams[0].a.to, 4);
  EXPECT_EQ(n.seams[0].b.from, 3);
  EXPECT_EQ(n.seams[0].b.to, 1);
  for (auto [sg, sn] : {std::pair{g.seams[0].a, n.seams[0].a}, std::pair{g.seams[0].b, n.seams[0].b}}) {
    const auto wg = stretchVertices(g, sg), wn = stretchVertices(n, sn);
    ASSERT_EQ(wg.size(), 3u);
    ASSERT_EQ(wn.size(), 3u);
    for (std::size_t i = 0; i < 3; ++i) EXPECT_EQ(g.panels[0].outline.row(wg[i]), n.panels[0].outline.row(wn[i]));
  }
}
