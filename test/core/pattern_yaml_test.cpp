// Patterns in YAML: the documented format, errors that name the key path with line and column,
// round trips, the example files, seam stages.
#include "pattern_helpers.h"
#include "virtual_tryon/core/drape/pattern.h"
#include "virtual_tryon/core/io/pattern_yaml.h"

#include <gtest/gtest.h>

#include <cmath>
#include <set>
#include <string>
#include <vector>

using namespace virtual_tryon;
using namespace virtual_tryon_test;

namespace {

std::string parseError(const std::string& text) {
  Pattern p;
  std::string error;
  EXPECT_FALSE(parsePatternYaml(text, p, error)) << text;
  return error;
}

const char* kTwoPanelYaml = R"(name: skirt
panels:
  - name: front
    outline: [[-0.2, 0.0], [0.2, 0.0], [0.2, 0.45], [-0.2, 0.45]]
    placement:
      translation: [0, 0.9, 0]
      rotation_rpy: [0, 0, 0]
      wrap_radius: 0.18
  - name: back
    outline: [[-0.2, 0.0], [0.2, 0.0], [0.2, 0.45], [-0.2, 0.45]]
    placement: {translation: [0, 0.9, 0], rotation_quaternion: [0, 1, 0, 0], wrap_radius: 0.18}
seams:
  - a: {panel: front, from: 1, to: 2}
    b: {panel: back, from: 0, to: 3}
  - a: {panel: 0, from: 0, to: 3}
    b: {panel: 1, from: 1, to: 2}
)";

}  // namespace

TEST(PatternYaml, ParsesTheDocumentedFormat) {
  Pattern p;
  std::string error;
  ASSERT_TRUE(parsePatternYaml(kTwoPanelYaml, p, error)) << error;
  EXPECT_EQ(p.name, "skirt");
  ASSERT_EQ(p.panels.size(), 2u);
  EXPECT_EQ(p.panels[1].name, "back");
  EXPECT_EQ(p.panels[0].outline.rows(), 4);
  EXPECT_DOUBLE_EQ(p.panels[0].outline(2, 1), 0.45);
  EXPECT_DOUBLE_EQ(p.panels[0].placement.wrap_radius, 0.18);
  EXPECT_TRUE(p.panels[0].placement.pose.translation().isApprox(Eigen::Vector3d(0, 0.9, 0)));
  EXPECT_TRUE(p.panels[0].placement.pose.linear().isIdentity(1e-15));
  // Quaternion [0, 1, 0, 0]: half a turn about y.
  EXPECT_LT((p.panels[1].placement.pose.linear() - Eigen::Matrix3d(Eigen::Vector3d(-1, 1, -1).asDiagonal()))
                .cwiseAbs()
                .maxCoeff(),
            1e-15);
  ASSERT_EQ(p.seams.size(), 2u);
  EXPECT_EQ(p.seams[0].b.panel, 1);
  EXPECT_EQ(p.seams[0].b.from, 0);
  EXPECT_EQ(p.seams[0].b.to, 3);
  EXPECT_EQ(p.seams[1].a.panel, 0);  // by index
  EXPECT_EQ(p.seams[1].b.panel, 1);
}

TEST(PatternYaml, RpyIsFixedAxesXYZ) {
  Pattern p;
  std::string error;
  ASSERT_TRUE(parsePatternYaml("panels:\n  - name: p\n    outline: [[0,0],[1,0],[0,1]]\n"
                               "    placement: {rotation_rpy: [0.1, 0.2, 0.3]}\n",
                               p, error))
      << error;
  const Eigen::Matrix3d expected = (Eigen::AngleAxisd(0.3, Eigen::Vector3d::UnitZ()) *
                                    Eigen::AngleAxisd(0.2, Eigen::Vector3d::UnitY()) *
                                    Eigen::AngleAxisd(0.1, Eigen::Vector3d::UnitX()))
                                       .toRotationMatrix();
  EXPECT_LT((p.panels[0].placement.pose.linear() - expected).cwiseAbs().maxCoeff(), 1e-15);
  EXPECT_EQ(p.name, "");
  EXPECT_TRUE(p.seams.empty());
}

TEST(PatternYaml, WrongTypesNameTheKeyPath) {
  const std::string head = "name: x\npanels:\n  - name: front\n";
  EXPECT_EQ(parseError(head + "    outline: square\n"),
            "panels[0].outline: expected a list of [u, v] points (metres, counter-clockwise), got 'square' "
            "(line 4, column 14)");
  EXPECT_EQ(parseError(head + "    outline: [[0, 0], [1, 0], abc, [0, 1]]\n"),
            "panels[0].outline[2]: expected a pair of numbers [u, v], got 'abc' (line 4, column 31)");
  EXPECT_EQ(parseError(head + "    outline: [[0, 0], [1, 0], [1, 1, 1]]\n"),
            "panels[0].outline[2]: expected a pair of numbers [u, v], got a list of 3 items (line 4, column 31)");
  EXPECT_EQ(parseError(head + "    outline: [[0, 0], [1, 0], [1, one]]\n"),
            "panels[0].outline[2][1]: expected a number, got 'one' (line 4, column 35)");
  EXPECT_EQ(parseError(head + "    outline: [[0, 0], [1, 0], [1, .nan]]\n"),
            "panels[0].outline[2][1]: expected a finite number, got '.nan' (line 4, column 35)");
  EXPECT_EQ(parseError(head + "    outline: [[0, 0], [1, 0]]\n"),
            "panels[0].outline: expected at least 3 points, got 2 (line 4, column 14)");
  const std::string tri = head + "    outline: [[0, 0], [1, 0], [0, 1]]\n";
  EXPECT_EQ(parseError(tri + "    placement:\n      wrap_radius: [0.2]\n"),
            "panels[0].placement.wrap_radius: expected a number, got a list of 1 item (line 6, column 20)");
  EXPECT_EQ(parseError(tri + "    placement:\n      wrap_radius: -0.2\n"),
            "panels[0].placement.wrap_radius: expected a radius >= 0 (0: flat), got '-0.2' (line 6, column 20)");
  EXPECT_EQ(parseError(tri + "    placement:\n      translation: [0, 1]\n"),
            "panels[0].placement.translation: expected a list of 3 numbers [x, y, z] (metres), got a list of 2 "
            "items (line 6, column 20)");
  EXPECT_EQ(parseError(tri + "    placement: {rotation_rpy: [0, 0, 0], rotation_quaternion: [0, 0, 0, 1]}\n"),
            "panels[0].placement: give either rotation_rpy or rotation_quaternion, not both (line 5, column 16)");
  EXPECT_EQ(parseError(tri + "    placement: {rotation_quaternion: [0, 0, 0, 0]}\n"),
            "panels[0].placement.rotation_quaternion: the quaternion is zero (line 5, column 38)");
  EXPECT_EQ(parseError(tri + "    placement: flat\n"),
            "panels[0].placement: expected a map with keys translation, rotation_rpy, rotation_quaternion, "
            "wrap_radius, got 'flat' (line 5, column 16)");
  EXPECT_EQ(parseError("panels: front\n"), "panels: expected a list of panels, got 'front' (line 1, column 9)");
  EXPECT_EQ(parseError("panels: []\n"),
            "panels: the list is empty; a pattern needs at least one panel (line 1, column 9)");
  EXPECT_EQ(parseError("- a\n- b\n"),
            "pattern: expected a map with keys name, panels, seams, got a list of 2 items (line 1, column 1)");
  EXPECT_EQ(parseError(""), "pattern: expected a map with keys name, panels, seams, got nothing");
  EXPECT_EQ(parseError(tri + "seams: {a: 1}\n"), "seams: expected a list of seams, got a map (line 5, column 8)");
  EXPECT_EQ(parseError(tri + "seams:\n  - a: {panel: front, from: 0, to: 1.5}\n    b: {panel: front, from: 1, to: 2}\n"),
            "seams[0].a.to: expected an outline point index (a whole number), got '1.5' (line 6, column 36)");
}

TEST(PatternYaml, MissingUnknownAndDuplicateKeys) {
  EXPECT_EQ(parseError("name: x\n"), "pattern: missing key 'panels' (line 1, column 1)");
  EXPECT_EQ(parseError("panels:\n  - name: front\n"), "panels[0]: missing key 'outline' (line 2, column 5)");
  EXPECT_EQ(parseError("panels:\n  - outline: [[0, 0], [1, 0], [0, 1]]\n"),
            "panels[0]: missing key 'name' (line 2, column 5)");
  EXPECT_EQ(parseError("panels:\n  - name: front\n    outlines: [[0, 0], [1, 0], [0, 1]]\n"),
            "panels[0]: unknown key 'outlines' (expected name, outline, placement) (line 3, column 5)");
  EXPECT_EQ(parseError("panels:\n  - name: front\n    name: back\n    outline: [[0, 0], [1, 0], [0, 1]]\n"),
            "panels[0]: duplicate key 'name' (line 3, column 5)");
  EXPECT_EQ(parseError("panels:\n  - name: \"\"\n    outline: [[0, 0], [1, 0], [0, 1]]\n"),
            "panels[0].name: expected a non-empty panel name, got '' (line 2, column 11)");
  EXPECT_EQ(parseError("panels:\n  - {name: a, outline: [[0, 0], [1, 0], [0, 1]]}\n"
                       "  - {name: a, outline: [[0, 0], [1, 0], [0, 1]]}\n"),
            "panels[1].name: duplicate panel name 'a' (also panels[0]) (line 3, column 12)");
  const std::string two = "panels:\n  - {name: front, outline: [[0, 0], [1, 0], [1, 1], [0, 1]]}\n"
                          "  - {name: back, outline: [[0, 0], [1, 0], [1, 1], [0, 1]]}\n";
  EXPECT_EQ(parseError(two + "seams:\n  - a: {panel: front, from: 1, to: 2}\n"),
            "seams[0]: missing key 'b' (line 5, column 5)");
  EXPECT_EQ(parseError(two + "seams:\n  - a: {panel: front, from: 1}\n    b: {panel: back, from: 0, to: 3}\n"),
            "seams[0].a: missing key 'to' (line 5, column 8)");
  EXPECT_EQ(parseError(two + "seams:\n  - a: {panel: front, from: 1, to: 2, dir: up}\n    b: {panel: back, from: 0, to: 3}\n"),
            "seams[0].a: unknown key 'dir' (expected panel, from, to) (line 5, column 39)");
}

TEST(PatternYaml, SeamReferences) {
  const std::string two = "panels:\n  - {name: front, outline: [[0, 0], [1, 0], [1, 1], [0, 1]]}\n"
                          "  - {name: back, outline: [[0, 0], [1, 0], [1, 1], [0, 1]]}\n";
  EXPECT_EQ(parseError(two + "seams:\n  - a: {panel: front, from: 1, to: 2}\n    b: {panel: bak, from: 0, to: 3}\n"),
            "seams[0].b.panel: unknown panel 'bak' (panels: 'front', 'back') (line 6, column 16)");
  EXPECT_EQ(parseError(two + "seams:\n  - a: {panel: 2, from: 1, to: 2}\n    b: {panel: back, from: 0, to: 3}\n"),
            "seams[0].a.panel: panel index 2 is out of range (the pattern has 2 panels, 0..1) (line 5, column 16)");
  EXPECT_EQ(parseError(two + "seams:\n  - a: {panel: front, from: 1, to: 4}\n    b: {panel: back, from: 0, to: 3}\n"),
            "seams[0].a.to: outline point 4 is out of range for panel 'front' (4 points, 0..3) (line 5, column 36)");
  EXPECT_EQ(parseError(two + "seams:\n  - a: {panel: front, from: 1, to: 2}\n    b: {panel: back, from: 3, to: 3}\n"),
            "seams[0].b: from == to (3); a stretch needs two distinct outline points (line 6, column 8)");
  // Geometric problems come from validatePattern.
  EXPECT_EQ(parseError(two + "seams:\n  - a: {panel: front, from: 1, to: 3}\n    b: {panel: back, from: 0, to: 3}\n"),
            "seam 0: a (panel 'front' (index 0), 1 -> 3) goes exactly half-way round the 4-point outline, so its "
            "direction is ambiguous; split the seam in two");
  EXPECT_EQ(parseError("panels:\n  - {name: bow, outline: [[0, 0], [1, 1], [1, 0], [0, 1]]}\n"),
            "panel 'bow' (index 0): outline is self-intersecting: edge 0 (points 0-1) meets edge 2 (points 2-3)");
  // A panel whose name looks like an index is found by name first.
  Pattern p;
  std::string error;
  ASSERT_TRUE(parsePatternYaml("panels:\n  - {name: x, outline: [[0, 0], [1, 0], [1, 1], [0, 1]]}\n"
                               "  - {name: '0', outline: [[0, 0], [1, 0], [1, 1], [0, 1]]}\n"
                               "seams:\n  - a: {panel: 0, from: 1, to: 2}\n    b: {panel: x, from: 0, to: 3}\n",
                               p, error))
      << error;
  EXPECT_EQ(p.seams[0].a.panel, 1);
  EXPECT_EQ(p.seams[0].b.panel, 0);
}

TEST(PatternYaml, SyntaxErrorsGiveLineAndColumn) {
  EXPECT_EQ(parseError("name: x\npanels:\n  - name: front\n    outline: [[0, 0], [1, 0]\n"),
            "YAML syntax error at line 5, column 1: end of sequence flow not found");
  EXPECT_EQ(parseError("name: x\npanels:\n  - name: front\n   bad: [\n"),
            "YAML syntax error at line 4, column 4: end of sequence not found");
}

TEST(PatternYaml, FailureLeavesThePatternAndNeverThrows) {
  Pattern p = tube(0.2, 0.5);
  std::string error;
  EXPECT_NO_THROW(EXPECT_FALSE(parsePatternYaml("panels: [{name: a, outline: [[0, 0], [1, 0]]}]", p, error)));
  EXPECT_EQ(p.panels.size(), 2u);
  EXPECT_NO_THROW(EXPECT_FALSE(parsePatternYaml("{{{{", p, error)));
  EXPECT_NO_THROW(EXPECT_FALSE(parsePatternYaml("panels: [{name: a, outline: !!binary AAAA}]", p, error)));
  EXPECT_NO_THROW(EXPECT_FALSE(parsePatternYaml("\t\x01\xff: [", p, error)));
  EXPECT_NO_THROW(EXPECT_FALSE(readPatternYaml("/nonexistent/pattern.yaml", p, error)));
  EXPECT_EQ(error, "/nonexistent/pattern.yaml: cannot open the pattern file");
  EXPECT_EQ(p.panels.size(), 2u);
}

TEST(PatternYaml, RoundTrip) {
  Pattern g = tube(0.2, 0.5);
  g.name = "round: trip #1";
  g.panels[0].name = "front \"left\"";
  g.panels[0].placement.pose.translation() = Eigen::Vector3d(0.1, 0.9, -1.0 / 3);
  g.panels[0].placement.pose.linear() =
      Eigen::Quaterniond(0.3, -0.5, 0.7, 0.1).normalized().toRotationMatrix();  // generic: as rpy or quaternion
  g.panels[1].placement.pose.linear() =
      Eigen::AngleAxisd(kPi / 2, Eigen::Vector3d::UnitY()).toRotationMatrix();  // gimbal lock
  g.panels.push_back(PatternPanel{"null", outlineOf({{0.1, 0.2}, {1e-3, 1e-17}, {-1e5, 7.123456789012345}}), PanelPlacement()});
  g.seams.push_back(seamOf(st(2, 0, 1), st(2, 1, 2)));
  ASSERT_EQ(validatePattern(g, 1e9), "");
  const std::string text = patternToYaml(g);
  Pattern back;
  std::string error;
  // The 1e5 edge against a 0.1 edge would fail the default length check: drop that seam to parse.
  Pattern loadable = g;
  loadable.seams.pop_back();
  ASSERT_TRUE(parsePatternYaml(patternToYaml(loadable), back, error)) << error << "\n" << patternToYaml(loadable);
  expectSamePattern(loadable, back, 1e-12);
  // Exact for outlines, translations and radii; the rotations within rounding.
  EXPECT_EQ(back.panels[2].outline, loadable.panels[2].outline);
  EXPECT_EQ(back.panels[0].placement.pose.translation(), loadable.panels[0].placement.pose.translation());
  // And again (rotations may move in the last digit, outlines do not).
  Pattern again;
  ASSERT_TRUE(parsePatternYaml(patternToYaml(back), again, error)) << error;
  expectSamePattern(loadable, again, 1e-12);
  EXPECT_EQ(again.panels[0].outline, loadable.panels[0].outline);
  EXPECT_NE(text.find("seams:"), std::string::npos);

  // Duplicate names: seams written by index.
  Pattern dup = tube(0.2, 0.5);
  dup.panels[1].name = "front";
  const std::string dupText = patternToYaml(dup);
  EXPECT_NE(dupText.find("{panel: 1, from: 0, to: 3}"), std::string::npos) << dupText;
}

TEST(PatternYaml, ExampleFiles) {
  Pattern skirt, sheet;
  std::string error;
  ASSERT_TRUE(readPatternYaml(VIRTUAL_TRYON_SOURCE_DIR "/config/patterns/examples/tube_skirt.yaml", skirt, error))
      << error;
  ASSERT_TRUE(readPatternYaml(VIRTUAL_TRYON_SOURCE_DIR "/config/patterns/examples/flat_sheet.yaml", sheet, error))
      << error;
  EXPECT_EQ(skirt.name, "tube_skirt");
  ASSERT_EQ(skirt.panels.size(), 2u);
  ASSERT_EQ(skirt.seams.size(), 2u);
  EXPECT_EQ(sheet.panels.size(), 1u);
  EXPECT_TRUE(sheet.seams.empty());

  ClothMesh c;
  ASSERT_TRUE(meshPattern(skirt, 0.02, c, error)) << error;
  // Round the body's vertical axis at 0.2 m, hem at y = 0.55, waist at 1.05.
  for (Eigen::Index n = 0; n < c.X.rows(); ++n) {
    EXPECT_NEAR(std::hypot(c.X(n, 0), c.X(n, 2)), 0.2, 1e-12);
    EXPECT_GE(c.X(n, 1), 0.55 - 1e-12);
    EXPECT_LE(c.X(n, 1), 1.05 + 1e-12);
  }
  for (int seam = 0; seam < 2; ++seam) {
    const auto pairs = pairsOfSeam(c, seam);
    // The slanted sides (0.52 m) in 2 cm steps, ends included: 27 nodes each, paired one to one.
    EXPECT_EQ(pairs.size(), 27u);
    std::set<int> nodesA, nodesB;
    for (const SeamPair& p : pairs) {
      nodesA.insert(p.a);
      nodesB.insert(p.b);
      EXPECT_NEAR(c.X(p.a, 1), c.X(p.b, 1), 1e-9);               // hem to hem, waist to waist
      EXPECT_LT((c.X.row(p.a) - c.X.row(p.b)).norm(), 0.06);     // a few cm apart on a 0.6 m panel
    }
    EXPECT_EQ(nodesA.size(), pairs.size());
    EXPECT_EQ(nodesB.size(), pairs.size());
  }
  expectConformingMesh(skirt, c, 0.02);
  ASSERT_TRUE(meshPattern(sheet, 0.05, c, error)) << error;
  EXPECT_EQ(c.X.rows(), 17 * 13);
  for (Eigen::Index t = 0; t < c.F.rows(); ++t) EXPECT_GT(triNormal(c, t).y(), 0.999999);  // faces up
  EXPECT_NEAR(c.X.col(1).minCoeff(), 1.9, 1e-12);
  EXPECT_NEAR(c.X.col(1).maxCoeff(), 1.9, 1e-12);
}

TEST(PatternYaml, SeamStages) {
  const std::string base(kTwoPanelYaml);
  Pattern p;
  std::string error;
  ASSERT_TRUE(parsePatternYaml(base, p, error)) << error;
  EXPECT_EQ(p.seams[0].stage, 0);  // absent: stage 0
  const std::string staged = base + "    stage: 2\n";
  ASSERT_TRUE(parsePatternYaml(staged, p, error)) << error;
  EXPECT_EQ(p.seams[1].stage, 2);
  Pattern back;
  ASSERT_TRUE(parsePatternYaml(patternToYaml(p), back, error)) << error;
  EXPECT_EQ(back.seams[1].stage, 2);
  EXPECT_EQ(back.seams[0].stage, 0);
  EXPECT_FALSE(parsePatternYaml(base + "    stage: -1\n", p, error));
  EXPECT_NE(error.find("seams[1].stage"), std::string::npos) << error;
  EXPECT_FALSE(parsePatternYaml(base + "    stage: first\n", p, error));
  EXPECT_NE(error.find("seams[1].stage"), std::string::npos) << error;
  ClothMesh cloth;
  ASSERT_TRUE(parsePatternYaml(staged, p, error));
  ASSERT_TRUE(meshPattern(p, 0.05, cloth, error)) << error;
  EXPECT_EQ(cloth.seam_stage, (std::vector<int>{0, 2}));
}
