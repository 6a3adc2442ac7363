// Outline stretches: the points a stretch walks through and its length.
#include "pattern_helpers.h"
#include "virtual_tryon/core/drape/pattern.h"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

using namespace virtual_tryon;
using namespace virtual_tryon_test;

TEST(Stretch, WalksTheShortWayRoundInTheGivenDirection) {
  Pattern g;
  g.panels.push_back(PatternPanel{"hex", outlineOf({{0, 0}, {1, 0}, {2, 1}, {2, 2}, {1, 2}, {0, 1}}), PanelPlacement()});
  EXPECT_EQ(stretchVertices(g, st(0, 1, 2)), (std::vector<int>{1, 2}));
  EXPECT_EQ(stretchVertices(g, st(0, 2, 1)), (std::vector<int>{2, 1}));
  EXPECT_EQ(stretchVertices(g, st(0, 5, 1)), (std::vector<int>{5, 0, 1}));
  EXPECT_EQ(stretchVertices(g, st(0, 1, 5)), (std::vector<int>{1, 0, 5}));
  EXPECT_EQ(stretchVertices(g, st(0, 4, 2)), (std::vector<int>{4, 3, 2}));
  EXPECT_TRUE(stretchVertices(g, st(0, 1, 1)).empty());
  EXPECT_TRUE(stretchVertices(g, st(1, 0, 1)).empty());
  EXPECT_TRUE(stretchVertices(g, st(0, 0, 6)).empty());
  EXPECT_NEAR(stretchLength(g, st(0, 5, 1)), 2.0, 1e-12);
  EXPECT_NEAR(stretchLength(g, st(0, 1, 5)), 2.0, 1e-12);
  EXPECT_NEAR(stretchLength(g, st(0, 1, 3)), 1 + std::sqrt(2.0), 1e-12);
  EXPECT_NEAR(stretchLength(g, st(0, 3, 4)), 1.0, 1e-12);
  EXPECT_EQ(stretchLength(g, st(0, 3, 3)), 0.0);
}
