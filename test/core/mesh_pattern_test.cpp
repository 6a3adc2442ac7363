// Meshing a pattern into grids of mass points: counts, rest lengths, boundary nodes snapped onto
// the outline, normals, clipping, seams paired node to node, errors, speed.
#include "pattern_helpers.h"
#include "virtual_tryon/core/drape/pattern.h"
#include "virtual_tryon/core/io/pattern_yaml.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <map>
#include <set>
#include <string>
#include <utility>
#include <vector>

using namespace virtual_tryon;
using namespace virtual_tryon_test;

namespace {

std::map<SpringType, std::vector<double>> restsByType(const ClothMesh& c) {
  std::map<SpringType, std::vector<double>> m;
  for (const Spring& s : c.springs) m[s.type].push_back(s.rest);
  return m;
}

}  // namespace

TEST(MeshPattern, RectangleGridCountsAndRestLengths) {
  Pattern g;
  g.panels.push_back(rectPanel("sheet", 0, 0, 1.0, 0.5));
  ClothMesh c;
  std::string error;
  ASSERT_TRUE(meshPattern(g, 0.1, c, error)) << error;
  EXPECT_EQ(c.X.rows(), 66);  // 11 x 6
  EXPECT_EQ(c.UV.rows(), 66);
  EXPECT_EQ(c.panel.size(), 66u);
  EXPECT_EQ(c.quads.size(), 50u);
  EXPECT_EQ(c.F.rows(), 100);
  EXPECT_DOUBLE_EQ(c.spacing, 0.1);
  EXPECT_TRUE(c.seam_pairs.empty());
  auto rests = restsByType(c);
  ASSERT_EQ(rests[SpringType::Structural].size(), 115u);  // 10 * 6 + 11 * 5
  ASSERT_EQ(rests[SpringType::Shear].size(), 100u);       // 2 * 50
  ASSERT_EQ(rests[SpringType::Flexion].size(), 98u);      // 9 * 6 + 11 * 4
  for (double r : rests[SpringType::Structural]) EXPECT_NEAR(r, 0.1, 1e-12);
  for (double r : rests[SpringType::Shear]) EXPECT_NEAR(r, 0.1 * std::sqrt(2.0), 1e-12);
  for (double r : rests[SpringType::Flexion]) EXPECT_NEAR(r, 0.2, 1e-12);
  // Rest lengths are the UV distances; no spring twice, none degenerate.
  std::set<std::pair<int, int>> seen;
  for (const Spring& s : c.springs) {
    ASSERT_NE(s.a, s.b);
    EXPECT_NEAR(s.rest, (c.UV.row(s.a) - c.UV.row(s.b)).norm(), 1e-15);
    EXPECT_TRUE(seen.insert({std::min(s.a, s.b), std::max(s.a, s.b)}).second) << s.a << "-" << s.b;
  }
  // The grid covers the rectangle exactly: corners are nodes.
  EXPECT_NEAR(c.UV.col(0).minCoeff(), 0.0, 1e-12);
  EXPECT_NEAR(c.UV.col(0).maxCoeff(), 1.0, 1e-12);
  EXPECT_NEAR(c.UV.col(1).maxCoeff(), 0.5, 1e-12);
  // Flat identity placement: X = (u, v, 0); triangle normals +z.
  for (Eigen::Index n = 0; n < c.X.rows(); ++n) {
    EXPECT_NEAR(c.X(n, 0), c.UV(n, 0), 1e-15);
    EXPECT_NEAR(c.X(n, 1), c.UV(n, 1), 1e-15);
    EXPECT_EQ(c.X(n, 2), 0.0);
  }
  for (Eigen::Index t = 0; t < c.F.rows(); ++t) EXPECT_GT(triNormal(c, t).z(), 0.999999) << "triangle " << t;
  // Quads go round counter-clockwise in uv and match their two triangles.
  for (std::size_t q = 0; q < c.quads.size(); ++q) {
    const auto& k = c.quads[q];
    double twice = 0;
    for (int i = 0; i < 4; ++i)
      twice += c.UV(k[i], 0) * c.UV(k[(i + 1) % 4], 1) - c.UV(k[(i + 1) % 4], 0) * c.UV(k[i], 1);
    EXPECT_NEAR(twice, 2 * 0.01, 1e-12);
    EXPECT_EQ(c.F(2 * q, 0), k[0]);
    EXPECT_EQ(c.F(2 * q + 1, 2), k[3]);
  }
}

TEST(MeshPattern, GridIsCentredOnTheBoundingBoxAndBoundaryNodesSnapToTheOutline) {
  Pattern g;
  g.panels.push_back(rectPanel("p", 0, 0, 1.05, 0.5));
  ClothMesh c;
  std::string error;
  ASSERT_TRUE(meshPattern(g, 0.1, c, error)) << error;
  EXPECT_EQ(c.X.rows(), 66);
  // The grid columns lie at 0.025 .. 1.025; the outermost ones move out onto the cut edges (0 and
  // 1.05), so the meshed panel is as wide as the pattern. Rest lengths follow the moved nodes.
  EXPECT_NEAR(c.UV.col(0).minCoeff(), 0.0, 1e-12);
  EXPECT_NEAR(c.UV.col(0).maxCoeff(), 1.05, 1e-12);
  int inner = 0;
  for (Eigen::Index n = 0; n < c.UV.rows(); ++n) inner += std::abs(c.UV(n, 0) - 0.525) < 1e-9;
  EXPECT_EQ(inner, 6);  // the middle column stays on the grid
  for (const Spring& s : c.springs) EXPECT_NEAR(s.rest, (c.UV.row(s.a) - c.UV.row(s.b)).norm(), 1e-15);
}

TEST(MeshPattern, BoundaryNodesOfASlantedEdgeSnapOntoIt) {
  // A trapezoid whose slanted sides cut the grid rows between nodes. Every node that lacks a
  // structural neighbour moves onto the outline (never past it), so the meshed quads cover the
  // whole panel; the grid alone would miss up to two spacings along each slanted side.
  Pattern g;
  PatternPanel p;
  p.name = "t";
  p.outline.resize(4, 2);
  p.outline << -0.5, 0, 0.5, 0, 0.3, 0.6, -0.3, 0.6;
  g.panels.push_back(p);
  ClothMesh c;
  std::string error;
  ASSERT_TRUE(meshPattern(g, 0.07, c, error)) << error;
  auto toOutline = [](double u, double v) {
    const double side = (std::abs(u) - (0.5 - v / 3)) / std::sqrt(1 + 1.0 / 9);  // signed, > 0 outside
    return std::min({std::abs(side), std::abs(v), std::abs(v - 0.6)});
  };
  std::vector<int> neighbours(static_cast<std::size_t>(c.UV.rows()), 0);
  for (const Spring& s : c.springs)
    if (s.type == SpringType::Structural) ++neighbours[s.a], ++neighbours[s.b];
  int boundary = 0;
  for (Eigen::Index n = 0; n < c.UV.rows(); ++n) {
    const double u = c.UV(n, 0), v = c.UV(n, 1);
    EXPECT_LE(std::abs(u), 0.5 - v / 3 + 1e-9) << "node " << n << " outside the outline";
    EXPECT_GE(v, -1e-9);
    EXPECT_LE(v, 0.6 + 1e-9);
    if (neighbours[static_cast<std::size_t>(n)] < 4) {
      ++boundary;
      EXPECT_LT(toOutline(u, v), 1e-9) << "boundary node " << n << " at (" << u << ", " << v << ")";
    }
  }
  EXPECT_GT(boundary, 20);
  double area = 0;
  for (const auto& q : c.quads)
    for (int i = 0; i < 4; ++i)
      area += 0.5 * (c.UV(q[i], 0) * c.UV(q[(i + 1) % 4], 1) - c.UV(q[(i + 1) % 4], 0) * c.UV(q[i], 1));
  EXPECT_LE(area, 0.48 + 1e-9);
  EXPECT_GT(area, 0.95 * 0.48);
  EXPECT_LT(static_cast<double>(c.quads.size()) * 0.07 * 0.07, 0.85 * 0.48);  // the grid alone
}

TEST(MeshPattern, NormalsFollowThePoseAndPointOutwardOnAWrap) {
  Pattern g;
  g.panels.push_back(rectPanel("p", -0.3, 0, 0.3, 0.4));
  g.panels[0].placement.pose.linear() =
      Eigen::AngleAxisd(-kPi / 2, Eigen::Vector3d::UnitX()).toRotationMatrix();  // faces +y
  ClothMesh c;
  std::string error;
  ASSERT_TRUE(meshPattern(g, 0.05, c, error)) << error;
  for (Eigen::Index t = 0; t < c.F.rows(); ++t) EXPECT_GT(triNormal(c, t).y(), 0.999999);

  g.panels[0].placement.pose = Eigen::Isometry3d::Identity();
  g.panels[0].placement.pose.translation() = Eigen::Vector3d(0.2, 1.0, 0.1);
  g.panels[0].placement.wrap_radius = 0.15;
  ASSERT_TRUE(meshPattern(g, 0.05, c, error)) << error;
  for (Eigen::Index n = 0; n < c.X.rows(); ++n)
    EXPECT_NEAR(std::hypot(c.X(n, 0) - 0.2, c.X(n, 2) - 0.1), 0.15, 1e-12);
  for (Eigen::Index t = 0; t < c.F.rows(); ++t) {
    Eigen::Vector3d centre = (c.X.row(c.F(t, 0)) + c.X.row(c.F(t, 1)) + c.X.row(c.F(t, 2))).transpose() / 3;
    Eigen::Vector3d radial(centre.x() - 0.2, 0, centre.z() - 0.1);
    EXPECT_GT(triNormal(c, t).dot(radial.normalized()), 0.99) << "triangle " << t;
  }
}

TEST(MeshPattern, TriangleOutlineIsClipped) {
  Pattern g;
  g.panels.push_back(PatternPanel{"tri", outlineOf({{0, 0}, {1, 0}, {0, 1}}), PanelPlacement()});
  ClothMesh c;
  std::string error;
  ASSERT_TRUE(meshPattern(g, 0.1, c, error)) << error;
  // Kept: i + j <= 10 (66 nodes, the hypotenuse nodes count as inside); quads: i + j <= 8 (45);
  // the two acute corners (10, 0) and (0, 10) belong to no quad and are dropped.
  EXPECT_EQ(c.quads.size(), 45u);
  EXPECT_EQ(c.X.rows(), 64);
  bool hypotenuseNode = false;
  for (Eigen::Index n = 0; n < c.UV.rows(); ++n) {
    EXPECT_LE(c.UV(n, 0) + c.UV(n, 1), 1 + 1e-9);
    EXPECT_FALSE(std::abs(c.UV(n, 0) - 1) < 1e-9 && std::abs(c.UV(n, 1)) < 1e-9) << "corner (1, 0) is isolated";
    hypotenuseNode = hypotenuseNode || (std::abs(c.UV(n, 0) - 0.7) < 1e-9 && std::abs(c.UV(n, 1) - 0.3) < 1e-9);
  }
  EXPECT_TRUE(hypotenuseNode);
  auto rests = restsByType(c);
  EXPECT_EQ(rests[SpringType::Structural].size(), 108u);
  // Diagonals (i,j)-(i+1,j+1) for i + j <= 8 (45); anti-diagonals along i + j <= 9 without the
  // dropped corners (45 + 8).
  EXPECT_EQ(rests[SpringType::Shear].size(), 98u);
  for (Eigen::Index t = 0; t < c.F.rows(); ++t) EXPECT_GT(triNormal(c, t).z(), 0.999999);
}

TEST(MeshPattern, NarrowNotchIsNotBridged) {
  // A 1 x 1 square with a slit 2 cm wide from the top down to v = 0.5, between grid columns
  // u = 0.4 and u = 0.5: no spring or quad may cross it above v = 0.5.
  Pattern g;
  g.panels.push_back(PatternPanel{"slit",
                           outlineOf({{0, 0}, {1, 0}, {1, 1}, {0.46, 1}, {0.46, 0.55}, {0.44, 0.55}, {0.44, 1}, {0, 1}}),
                           PanelPlacement()});
  ClothMesh c;
  std::string error;
  ASSERT_TRUE(meshPattern(g, 0.1, c, error)) << error;
  EXPECT_EQ(c.X.rows(), 121);
  int crossingBelow = 0;
  for (const Spring& s : c.springs) {
    const double ua = c.UV(s.a, 0), ub = c.UV(s.b, 0);
    if (std::min(ua, ub) < 0.45 && std::max(ua, ub) > 0.45) {
      EXPECT_LT(std::max(c.UV(s.a, 1), c.UV(s.b, 1)), 0.55 + 1e-9) << "spring " << s.a << "-" << s.b;
      ++crossingBelow;
    }
  }
  EXPECT_GT(crossingBelow, 0);
  for (const auto& q : c.quads) {
    if (c.UV(q[0], 0) < 0.45 && c.UV(q[1], 0) > 0.45) {
      EXPECT_LT(c.UV(q[2], 1), 0.5 + 1e-9);
    }
  }
  // 10 x 10 cells, minus the 5 cells in column 4 above v = 0.5.
  EXPECT_EQ(c.quads.size(), 95u);
}

TEST(MeshPattern, TubeSeamsPairNodesThatMeet) {
  const double r = 0.2, h = 0.5, spacing = 0.05;
  const Pattern g = tube(r, h);
  ASSERT_EQ(validatePattern(g), "");
  ClothMesh c;
  std::string error;
  ASSERT_TRUE(meshPattern(g, spacing, c, error)) << error;
  const int perPanel = static_cast<int>(c.X.rows()) / 2;
  EXPECT_EQ(perPanel, 13 * 11);  // floor(0.628 / 0.05) + 1 = 13 columns, 11 rows
  for (int n = 0; n < perPanel; ++n) EXPECT_EQ(c.panel[static_cast<std::size_t>(n)], 0);
  for (int n = perPanel; n < 2 * perPanel; ++n) EXPECT_EQ(c.panel[static_cast<std::size_t>(n)], 1);
  for (int seam = 0; seam < 2; ++seam) {
    const auto pairs = pairsOfSeam(c, seam);
    EXPECT_EQ(pairs.size(), 11u) << "seam " << seam;
    for (const SeamPair& p : pairs) {
      EXPECT_EQ(c.panel[static_cast<std::size_t>(p.a)], 0);
      EXPECT_EQ(c.panel[static_cast<std::size_t>(p.b)], 1);
      // Hem meets hem, row for row.
      EXPECT_NEAR(c.UV(p.a, 1), c.UV(p.b, 1), 1e-9);
      // The grid stops 1.4 cm short of each side: the gap is 2.8 cm round the cylinder, small
      // next to the 0.63 x 0.5 m panels.
      const double gap = (c.X.row(p.a) - c.X.row(p.b)).norm();
      EXPECT_LT(gap, 0.03) << "seam " << seam;
    }
    // And on the side the seam belongs to.
    EXPECT_GT(c.X(pairs[0].a, 0) * (seam == 0 ? 1 : -1), 0.19);
  }
}

TEST(MeshPattern, SeamDirectionMatters) {
  Pattern g = tube(0.2, 0.5);
  std::swap(g.seams[0].b.from, g.seams[0].b.to);  // back's left edge walked waist to hem
  ASSERT_EQ(validatePattern(g), "");
  ClothMesh c;
  std::string error;
  ASSERT_TRUE(meshPattern(g, 0.05, c, error)) << error;
  const auto pairs = pairsOfSeam(c, 0);
  ASSERT_EQ(pairs.size(), 11u);
  for (const SeamPair& p : pairs) EXPECT_NEAR(c.UV(p.a, 1) + c.UV(p.b, 1), 0.5, 1e-9);
  // The front's hem node is pulled to the back's waist.
  const SeamPair& hem = pairs.front();
  EXPECT_NEAR(c.UV(hem.a, 1), 0.0, 1e-9);
  EXPECT_NEAR(c.UV(hem.b, 1), 0.5, 1e-9);
  EXPECT_GT((c.X.row(hem.a) - c.X.row(hem.b)).norm(), 0.45);
  // The other seam is untouched.
  for (const SeamPair& p : pairsOfSeam(c, 1)) EXPECT_NEAR(c.UV(p.a, 1), c.UV(p.b, 1), 1e-9);
}

TEST(MeshPattern, SeamOnTheLongerSideGetsOnePairPerNode) {
  // Stretch a is 0.5 m (11 nodes at 5 cm), b is 0.4 m (9 nodes): 11 pairs, every node of a once.
  Pattern g;
  g.panels.push_back(rectPanel("long", 0, 0, 0.3, 0.5));
  g.panels.push_back(rectPanel("short", 0, 0, 0.3, 0.4));
  g.panels[1].placement.pose.translation() = Eigen::Vector3d(0.35, 0, 0);
  g.seams.push_back(seamOf(st(0, 1, 2), st(1, 0, 3)));
  ClothMesh c;
  std::string error;
  ASSERT_TRUE(meshPattern(g, 0.05, c, error)) << error;
  const auto pairs = pairsOfSeam(c, 0);
  ASSERT_EQ(pairs.size(), 11u);
  std::set<int> aNodes, bNodes;
  for (const SeamPair& p : pairs) {
    aNodes.insert(p.a);
    bNodes.insert(p.b);
    EXPECT_NEAR(c.UV(p.a, 0), 0.3, 1e-9);
    EXPECT_NEAR(c.UV(p.b, 0), 0.0, 1e-9);
  }
  EXPECT_EQ(aNodes.size(), 11u);
  EXPECT_EQ(bNodes.size(), 9u);
  EXPECT_NEAR(c.UV(pairs.front().b, 1), 0.0, 1e-9);
  EXPECT_NEAR(c.UV(pairs.back().b, 1), 0.4, 1e-9);
}

TEST(MeshPattern, DartOnOnePanelDropsTheTipPair) {
  // A dart: two stretches of the same panel meeting at the tip (point 3); the tip pairs with
  // itself and is dropped.
  Pattern g;
  g.panels.push_back(PatternPanel{"bodice",
                           outlineOf({{0, 0}, {0.6, 0}, {0.6, 0.6}, {0.35, 0.6}, {0.3, 0.3}, {0.25, 0.6}, {0, 0.6}}),
                           PanelPlacement()});
  g.seams.push_back(seamOf(st(0, 3, 4), st(0, 5, 4)));
  ASSERT_EQ(validatePattern(g), "");
  ClothMesh c;
  std::string error;
  ASSERT_TRUE(meshPattern(g, 0.025, c, error)) << error;
  const auto pairs = pairsOfSeam(c, 0);
  EXPECT_GE(pairs.size(), 2u);
  for (const SeamPair& p : pairs) {
    EXPECT_NE(p.a, p.b);
    EXPECT_GE(c.UV(p.a, 0), 0.3 - 1e-9);  // right leg of the dart (or its tip)
    EXPECT_LE(c.UV(p.b, 0), 0.3 + 1e-9);  // left leg
    EXPECT_NEAR(c.UV(p.a, 1), c.UV(p.b, 1), 0.03);
  }
}

TEST(MeshPattern, Errors) {
  ClothMesh c;
  std::string error;
  Pattern g;
  g.panels.push_back(rectPanel("small", 0, 0, 0.1, 0.05));
  EXPECT_FALSE(meshPattern(g, 0.1, c, error));
  EXPECT_EQ(error, "panel 'small' (index 0): no grid quad fits at spacing 0.1 m (outline bounding box 0.1 x 0.05 m)");
  EXPECT_EQ(c.X.rows(), 0);
  EXPECT_FALSE(meshPattern(g, 0, c, error));
  EXPECT_EQ(error, "grid spacing must be a finite number > 0, got 0");
  EXPECT_FALSE(meshPattern(g, 1e-5, c, error));
  EXPECT_EQ(error, "panel 'small' (index 0): spacing 1e-05 m gives a 10001 x 5001 grid, more than 20000000 nodes");

  // A seam along a 5 cm edge at 10 cm spacing: the edge's grid node belongs to no quad and is
  // dropped; only the corner node below it, snapped onto the outline, is near either stretch.
  Pattern s;
  for (const char* name : {"a", "b"})
    s.panels.push_back(PatternPanel{name, outlineOf({{0, 0}, {0.5, 0}, {0.5, 0.05}, {0.25, 0.5}, {0, 0.5}}), PanelPlacement()});
  s.seams.push_back(seamOf(st(0, 1, 2), st(1, 1, 2)));
  EXPECT_EQ(validatePattern(s), "");
  EXPECT_FALSE(meshPattern(s, 0.1, c, error));
  EXPECT_EQ(error,
            "seam 0: only 0 distinct node pairs at spacing 0.1 m (boundary nodes within 0.75 * spacing: 1 of "
            "panel 'a' (index 0) near a, 1 of panel 'b' (index 1) near b); a seam needs at least 2, use a finer "
            "spacing");
  EXPECT_TRUE(meshPattern(s, 0.025, c, error)) << error;
  // An invalid pattern is refused with validatePattern's message.
  s.seams[0].b.to = 9;
  EXPECT_FALSE(meshPattern(s, 0.025, c, error));
  EXPECT_EQ(error, validatePattern(s));
  EXPECT_EQ(c.X.rows(), 0);
}

TEST(MeshPattern, Meshes3840NodesInAFewMilliseconds) {
  // The paper's dress has 3840 vertices; our two-panel skirt at 1.25 cm has about as many.
  Pattern g;
  std::string error;
  ASSERT_TRUE(readPatternYaml(VIRTUAL_TRYON_SOURCE_DIR "/config/patterns/examples/tube_skirt.yaml", g, error)) << error;
  ClothMesh c;
  ASSERT_TRUE(meshPattern(g, 0.0125, c, error)) << error;  // warm-up
  double best = 1e9;
  for (int run = 0; run < 5; ++run) {
    const auto t0 = std::chrono::steady_clock::now();
    ASSERT_TRUE(meshPattern(g, 0.0125, c, error)) << error;
    best = std::min(best, std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count());
  }
  std::printf("[ timing   ] meshPattern: %d nodes, %zu springs, %zu seam pairs in %.2f ms\n",
              static_cast<int>(c.X.rows()), c.springs.size(), c.seam_pairs.size(), best);
  EXPECT_GT(c.X.rows(), 3500);
  EXPECT_LT(c.X.rows(), 4500);
  EXPECT_LT(best, 50.0);  // a few ms on a quiet machine; generous for shared CI
}
