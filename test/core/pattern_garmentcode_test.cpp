// GarmentCode's pattern specification: curves against closed forms, stitch direction, clockwise
// panels, units and rotations, every error, the placement rule, and a drape end to end.
#include "virtual_tryon/core/drape/drape.h"
#include "virtual_tryon/core/drape/pattern_placement.h"
#include "virtual_tryon/core/io/garmentcode_edges.h"
#include "virtual_tryon/core/io/pattern_garmentcode.h"
#include "virtual_tryon/core/io/pattern_yaml.h"
#include "virtual_tryon/core/scenes/procedural_body.h"
#include "virtual_tryon/testing/reference_bvh.h"
#include "virtual_tryon/testing/reference_check.h"

#include "test_helpers.h"

#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <memory>

using namespace virtual_tryon;
using namespace virtual_tryon_test;

namespace {

constexpr double kPi = 3.14159265358979323846;

GarmentCodeEdge edgeOf(GarmentCodeEdge::Type t, Eigen::Vector2d a, Eigen::Vector2d b) {
  GarmentCodeEdge e;
  e.type = t;
  e.start = a;
  e.end = b;
  return e;
}

// Two 10 x 10 cm squares, front at z = 5 cm and back at z = -5 cm, sewn along their right edges
// (edge 1 of each), with `curvature` on the front's edge 1 and a third stitch item when given.
std::string squares(const std::string& curvature = "", const std::string& stitchTag = "",
                    const std::string& units = "100") {
  return R"({"pattern": {"panels": {
    "front": {"translation": [0, 100, 5], "rotation": [0, 0, 0],
              "vertices": [[0, 0], [10, 0], [10, 10], [0, 10]],
              "edges": [{"endpoints": [0, 1]}, {"endpoints": [1, 2])" + curvature + R"(},
                        {"endpoints": [2, 3]}, {"endpoints": [3, 0]}]},
    "back": {"translation": [0, 100, -5], "rotation": [0, 0, 0],
             "vertices": [[0, 0], [10, 0], [10, 10], [0, 10]],
             "edges": [{"endpoints": [0, 1]}, {"endpoints": [1, 2]}, {"endpoints": [2, 3]}, {"endpoints": [3, 0]}]}},
    "stitches": [[{"panel": "front", "edge": 1}, {"panel": "back", "edge": 1})" + stitchTag + R"(]]},
   "properties": {"units_in_meter": )" + units + R"(, "curvature_coords": "relative"}})";
}

bool parse(const std::string& text, Pattern& p, GarmentCodeReport& r, std::string& err, double spacing = 0.02) {
  GarmentCodeReadParams params;
  params.spacing = spacing;
  return parseGarmentCodeJson(text, params, p, r, err);
}

Eigen::Vector3d placed(const Pattern& p, int panel, int vertex) {
  const PatternPanel& q = p.panels[static_cast<std::size_t>(panel)];
  return q.placement.place(q.outline.row(vertex).transpose());
}

std::string errorOf(const std::string& text) {
  Pattern p;
  GarmentCodeReport r;
  std::string err;
  EXPECT_FALSE(parse(text, p, r, err));
  EXPECT_FALSE(err.empty());
  return err;
}

// Replaces the first occurrence of `from` in `text`.
std::string with(std::string text, const std::string& from, const std::string& to) {
  const std::size_t at = text.find(from);
  EXPECT_NE(at, std::string::npos) << from;
  return at == std::string::npos ? text : text.replace(at, from.size(), to);
}

}  // namespace

TEST(GarmentCodeEdges, RelativeControlPointsFollowTheEdgeFrame) {
  // x along the edge, y to its left (perp(d) = (-d.y, d.x)), both scaled by the edge vector.
  const Eigen::Vector2d c = garmentCodeRelativeToAbsolute({1, 1}, {1, 5}, {0.25, 0.5});
  EXPECT_NEAR(c.x(), 1 - 2, 1e-12);
  EXPECT_NEAR(c.y(), 1 + 1, 1e-12);
}

TEST(GarmentCodeEdges, QuadraticAndCubicMatchTheirClosedForms) {
  GarmentCodeEdge q = edgeOf(GarmentCodeEdge::Type::Quadratic, {0, 0}, {10, 0});
  q.control[0] = {5, 5};
  for (double t : {0.0, 0.2, 0.5, 0.9, 1.0}) {
    const Eigen::Vector2d want = (1 - t) * (1 - t) * q.start + 2 * (1 - t) * t * q.control[0] + t * t * q.end;
    EXPECT_LT((edgePoint(q, t) - want).norm(), 1e-12) << t;
  }
  EXPECT_NEAR(edgePoint(q, 0.5).y(), 2.5, 1e-12);
  // Its length: the parabola y = x (10 - x) / 10 through (0,0), (5,2.5), (10,0), by Simpson's rule.
  const auto f = [](double x) { const double d = 1 - x / 5; return std::sqrt(1 + d * d); };
  double ref = 0;  // Simpson, 2000 panels
  for (int i = 0; i < 2000; ++i) {
    const double a = i * 10.0 / 2000, b = (i + 1) * 10.0 / 2000;
    ref += (b - a) / 6 * (f(a) + 4 * f(0.5 * (a + b)) + f(b));
  }
  EXPECT_NEAR(edgeLength(q), ref, 1e-9 * ref);

  GarmentCodeEdge c = edgeOf(GarmentCodeEdge::Type::Cubic, {0, 0}, {9, 0});
  c.control[0] = {3, 6};
  c.control[1] = {6, -6};
  EXPECT_LT((edgePoint(c, 0.5) - (c.start + 3 * c.control[0] + 3 * c.control[1] + c.end) / 8).norm(), 1e-12);
  // A cubic with its controls on the chord at thirds is the straight line: length 9.
  GarmentCodeEdge s = edgeOf(GarmentCodeEdge::Type::Cubic, {0, 0}, {9, 0});
  s.control[0] = {3, 0};
  s.control[1] = {6, 0};
  EXPECT_NEAR(edgeLength(s), 9.0, 1e-12);
}

TEST(GarmentCodeEdges, CircleArcsFollowTheSvgFlags) {
  // Chord (0,0) -> (2,0), radius 1: a half circle, below the chord (right of +x) when `right`.
  GarmentCodeEdge e = edgeOf(GarmentCodeEdge::Type::Circle, {0, 0}, {2, 0});
  e.radius = 1;
  e.right = true;
  EXPECT_LT((edgePoint(e, 0.5) - Eigen::Vector2d(1, -1)).norm(), 1e-12);
  EXPECT_NEAR(edgeLength(e), kPi, 1e-12);
  e.right = false;
  EXPECT_LT((edgePoint(e, 0.5) - Eigen::Vector2d(1, 1)).norm(), 1e-12);
  // Radius 2 on a chord of 2: the small arc spans 60 degrees, the large one 300.
  e.radius = 2;
  e.large_arc = false;
  EXPECT_NEAR(edgeLength(e), 2 * kPi / 3, 1e-12);
  const Eigen::Vector2d centreSmall(1, -std::sqrt(3.0));  // left (right = false), small arc: centre below
  for (double t : {0.1, 0.5, 0.8}) EXPECT_NEAR((edgePoint(e, t) - centreSmall).norm(), 2, 1e-12);
  EXPECT_GT(edgePoint(e, 0.5).y(), 0);
  e.large_arc = true;
  EXPECT_NEAR(edgeLength(e), 2 * 5 * kPi / 3, 1e-12);
  const Eigen::Vector2d centreLarge(1, std::sqrt(3.0));
  for (double t : {0.1, 0.5, 0.8}) EXPECT_NEAR((edgePoint(e, t) - centreLarge).norm(), 2, 1e-12);
  EXPECT_NEAR(edgePoint(e, 0.5).y(), std::sqrt(3.0) + 2, 1e-12);
  // Too small a radius is scaled up to half the chord.
  e.radius = 0.5;
  e.large_arc = false;
  EXPECT_NEAR(edgeLength(e), kPi, 1e-12);
}

TEST(GarmentCodeEdges, SamplesAreEvenlySpacedAlongTheCurve) {
  GarmentCodeEdge c = edgeOf(GarmentCodeEdge::Type::Cubic, {0, 0}, {9, 0});
  c.control[0] = {1, 8};
  c.control[1] = {8, 8};
  const MatrixX2d S = sampleEdge(c, 12);
  ASSERT_EQ(S.rows(), 13);
  EXPECT_EQ(Eigen::Vector2d(S.row(0)), c.start);
  EXPECT_EQ(Eigen::Vector2d(S.row(12)), c.end);
  // Each step covers 1/12 of the length (measured on a fine polyline between the samples).
  const double L = edgeLength(c);
  double prevT = 0;
  for (int k = 1; k <= 12; ++k) {
    double lo = prevT, hi = 1;  // the curve parameter of sample k
    for (int it = 0; it < 60; ++it) {
      const double mid = 0.5 * (lo + hi);
      ((edgePoint(c, mid) - Eigen::Vector2d(S.row(k))).dot(edgePoint(c, mid + 1e-7) - edgePoint(c, mid)) < 0 ? lo : hi) = mid;
    }
    double arc = 0;
    for (int i = 0; i < 2000; ++i)
      arc += (edgePoint(c, prevT + (lo - prevT) * (i + 1) / 2000) - edgePoint(c, prevT + (lo - prevT) * i / 2000)).norm();
    EXPECT_NEAR(arc, L / 12, 1e-4 * L) << k;
    prevT = lo;
  }
}

TEST(GarmentCodeReader, StitchesJoinTheStartOfOneEdgeToTheEndOfTheOther) {
  Pattern p;
  GarmentCodeReport r;
  std::string err;
  ASSERT_TRUE(parse(squares(), p, r, err)) << err;
  ASSERT_EQ(p.panels.size(), 2u);
  ASSERT_EQ(p.seams.size(), 1u);
  const PatternSeam& s = p.seams[0];
  // Front edge 1 runs (10,0) -> (10,10); back edge 1 too: unmarked, front's start meets back's end.
  EXPECT_LT((placed(p, s.a.panel, s.a.from) - Eigen::Vector3d(0.10, 1.00, 0.05)).norm(), 1e-12);
  EXPECT_LT((placed(p, s.b.panel, s.b.from) - Eigen::Vector3d(0.10, 1.10, -0.05)).norm(), 1e-12);
  EXPECT_LT((placed(p, s.a.panel, s.a.to) - Eigen::Vector3d(0.10, 1.10, 0.05)).norm(), 1e-12);
  EXPECT_LT((placed(p, s.b.panel, s.b.to) - Eigen::Vector3d(0.10, 1.00, -0.05)).norm(), 1e-12);
  EXPECT_FALSE(r.stitches[0].right_wrong);
  // "right_wrong": start meets start.
  ASSERT_TRUE(parse(squares("", R"(, "right_wrong")"), p, r, err)) << err;
  EXPECT_TRUE(r.stitches[0].right_wrong);
  EXPECT_LT((placed(p, p.seams[0].b.panel, p.seams[0].b.from) - Eigen::Vector3d(0.10, 1.00, -0.05)).norm(), 1e-12);
}

TEST(GarmentCodeReader, CurvedEdgesAreSampledAtTheSpacingOnBothSidesOfAStitch) {
  Pattern p;
  GarmentCodeReport r;
  std::string err;
  ASSERT_TRUE(parse(squares(R"(, "curvature": {"type": "quadratic", "params": [[0.5, 0.3]]})"), p, r, err, 0.01)) << err;
  const GarmentCodeStitch& st = r.stitches[0];
  EXPECT_GT(st.length_a, 0.10);
  EXPECT_NEAR(st.length_b, 0.10, 1e-12);
  EXPECT_EQ(st.segments, static_cast<int>(std::ceil(st.length_a / 0.01)));
  // Both outlines got the samples: 3 corners + segments each.
  EXPECT_EQ(p.panels[0].outline.rows(), 3 + st.segments);
  EXPECT_EQ(p.panels[1].outline.rows(), 3 + st.segments);
  // The bulge (to the edge's left, -x, into the panel) is on the closed form's curve.
  GarmentCodeEdge q = edgeOf(GarmentCodeEdge::Type::Quadratic, {10, 0}, {10, 10});
  q.control[0] = garmentCodeRelativeToAbsolute(q.start, q.end, {0.5, 0.3});
  EXPECT_LT(q.control[0].x(), 10);
  for (Eigen::Index i = 0; i < p.panels[0].outline.rows(); ++i) {
    const Eigen::Vector2d uv = p.panels[0].outline.row(i).transpose() * 100;
    if (uv.x() < 10 - 1e-9 && uv.y() > 1e-9 && uv.y() < 10 - 1e-9) {
      double best = 1e9;
      for (int k = 0; k <= 20000; ++k) best = std::min(best, (edgePoint(q, k / 20000.0) - uv).norm());
      EXPECT_LT(best, 1e-3) << i;
    }
  }
}

TEST(GarmentCodeReader, UnitsRotationsAndClockwisePanels) {
  Pattern p;
  GarmentCodeReport r;
  std::string err;
  // Millimetres: a 10 mm square.
  ASSERT_TRUE(parse(squares("", "", "1000"), p, r, err)) << err;
  EXPECT_NEAR(p.panels[0].outline.row(2).norm(), std::sqrt(2.0) * 0.010, 1e-12);
  EXPECT_NEAR(p.panels[0].placement.pose.translation().y(), 0.100, 1e-12);
  // Rotation [90, 0, 90] degrees: R = Rz(90) Ry(0) Rx(90) takes panel x -> 3D y, panel y -> 3D z.
  ASSERT_TRUE(parse(with(squares(), R"("rotation": [0, 0, 0],)", R"("rotation": [90, 0, 90],)"), p, r, err)) << err;
  const Eigen::Matrix3d R = p.panels[0].placement.pose.linear();
  EXPECT_LT((R * Eigen::Vector3d::UnitX() - Eigen::Vector3d::UnitY()).norm(), 1e-12);
  EXPECT_LT((R * Eigen::Vector3d::UnitY() - Eigen::Vector3d::UnitZ()).norm(), 1e-12);
  // A clockwise panel is mirrored: counter-clockwise, same 3D corners, its side turned 180 degrees.
  const std::string cw = with(squares(), R"("vertices": [[0, 0], [10, 0], [10, 10], [0, 10]],
              "edges")", R"("vertices": [[0, 0], [0, 10], [10, 10], [10, 0]],
              "edges")");
  ASSERT_TRUE(parse(cw, p, r, err)) << err;
  EXPECT_GT(outlineSignedArea(p.panels[0].outline), 0);
  EXPECT_LT((placed(p, 0, 1) - Eigen::Vector3d(0.0, 1.10, 0.05)).norm(), 1e-12);
  EXPECT_LT((placed(p, 0, 3) - Eigen::Vector3d(0.10, 1.00, 0.05)).norm(), 1e-12);
  EXPECT_LT((p.panels[0].placement.pose.linear().col(2) + Eigen::Vector3d::UnitZ()).norm(), 1e-12);
}

TEST(GarmentCodeReader, EveryErrorNamesItsPlace) {
  const std::string ok = squares();
  EXPECT_TRUE(contains(errorOf("{not json"), "not valid JSON"));
  EXPECT_TRUE(contains(errorOf("[1, 2]"), "JSON object"));
  EXPECT_TRUE(contains(errorOf(R"({"pattern": {}})"), "pattern.panels"));
  const std::string spline = errorOf(squares(R"(, "curvature": {"type": "spline", "params": [[0.5, 0.1]]})"));
  EXPECT_TRUE(contains(spline, "panel 'front' edge 1")) << spline;
  EXPECT_TRUE(contains(spline, "'spline' is not one of quadratic, cubic, circle")) << spline;
  EXPECT_TRUE(contains(errorOf(squares(R"(, "curvature": {"type": "cubic", "params": [[0.5, 0.1]]})")),
                       "takes 2 values, got 1"));
  EXPECT_TRUE(contains(errorOf(squares(R"(, "curvature": {"type": "circle", "params": [-3, 0, 1]})")), "radius"));
  const std::string range = errorOf(with(ok, R"({"endpoints": [2, 3]})", R"({"endpoints": [2, 7]})"));
  EXPECT_TRUE(contains(range, "panel 'front' edge 2.endpoints: vertex 7 out of range")) << range;
  EXPECT_TRUE(contains(errorOf(with(ok, R"({"endpoints": [3, 0]})", R"({"endpoints": [3, 1]})")), "edge 0 starts"));
  const std::string noPanel = errorOf(with(ok, R"({"panel": "back", "edge": 1})", R"({"panel": "sleeve", "edge": 1})"));
  EXPECT_TRUE(contains(noPanel, "stitch 0 side 1: no panel named 'sleeve'")) << noPanel;
  const std::string noEdge = errorOf(with(ok, R"({"panel": "back", "edge": 1})", R"({"panel": "back", "edge": 9})"));
  EXPECT_TRUE(contains(noEdge, "panel 'back' has no edge 9")) << noEdge;
  const std::string twice = errorOf(with(ok, R"({"panel": "back", "edge": 1})", R"({"panel": "front", "edge": 1})"));
  EXPECT_TRUE(contains(twice, "already sewn")) << twice;
  EXPECT_TRUE(contains(errorOf(squares("", R"(, "inside_out")")), "right_wrong"));
  EXPECT_TRUE(contains(errorOf(squares("", "", "0")), "units_in_meter"));
  EXPECT_TRUE(contains(errorOf(with(ok, "[10, 0], [10, 10]", R"([10, 0], ["a", 10])")), "front'.vertices[2]"));
  EXPECT_TRUE(contains(errorOf(with(ok, R"("curvature_coords": "relative")", R"("curvature_coords": "polar")")),
                       "curvature_coords"));
  Pattern p;
  GarmentCodeReport r;
  std::string err;
  GarmentCodeReadParams bad;
  bad.spacing = 0;
  EXPECT_FALSE(parseGarmentCodeJson(ok, bad, p, r, err));
  EXPECT_TRUE(contains(err, "spacing"));
  // A spacing so fine that the outlines would pass the limits is refused before they are sampled.
  bad.spacing = 1e-7;
  EXPECT_FALSE(parseGarmentCodeJson(squares(R"(, "curvature": {"type": "quadratic", "params": [[0.5, 0.3]]})"), bad,
                                    p, r, err));
  EXPECT_TRUE(contains(err, "more than")) << err;
  // From a file: the message starts with its path.
  EXPECT_FALSE(readGarmentCodeJson("/nonexistent/x.json", GarmentCodeReadParams(), p, r, err));
  EXPECT_TRUE(contains(err, "/nonexistent/x.json")) << err;
}

TEST(GarmentCodeReader, StitchesOfVeryDifferentLengthsWarnWithBothLengths) {
  Pattern p;
  GarmentCodeReport r;
  std::string err;
  // The front's edge 1 bulged into a half circle: pi * 5 cm against the back's 10 cm.
  ASSERT_TRUE(parse(squares(R"(, "curvature": {"type": "circle", "params": [5, 0, 0]})"), p, r, err)) << err;
  ASSERT_EQ(r.warnings.size(), 1u);
  EXPECT_TRUE(contains(r.warnings[0], "15.70")) << r.warnings[0];
  EXPECT_TRUE(contains(r.warnings[0], "10 cm")) << r.warnings[0];
  EXPECT_TRUE(contains(r.warnings[0], "takes in 5.70")) << r.warnings[0];
  // Past a ratio of 2 the pattern is refused (validatePattern): the large arc of radius 6 cm,
  // bulging out of the panel, is 25.9 cm.
  EXPECT_FALSE(parse(squares(R"(, "curvature": {"type": "circle", "params": [6, 1, 1]})"), p, r, err));
  EXPECT_TRUE(contains(err, "ratio")) << err;
}

TEST(GarmentCodeReader, ALongStitchIsSplitIntoSeamsShorterThanHalfAnOutline) {
  Pattern p;
  GarmentCodeReport r;
  std::string err;
  // The bulge makes edge 1 most of the front's outline.
  ASSERT_TRUE(parse(squares(R"(, "curvature": {"type": "cubic", "params": [[0.0, 0.4], [1.0, 0.4]]})"), p, r, err,
                    0.005)) << err;
  EXPECT_GT(r.stitches[0].seams.size(), 1u);
  EXPECT_EQ(validatePattern(p, 2.0), "");
  EXPECT_EQ(patternOpenings(p), 1);  // the squares' other three sides, one loop
}

TEST(GarmentCodePlacement, FloorAndTorsoCentreOfTheProceduralBody) {
  const TriMesh body = makeProceduralBody();
  const BodyPlacement pl = placementOnBody(body.V);
  EXPECT_NEAR(pl.floor, body.V.col(1).minCoeff(), 1e-12);
  EXPECT_NEAR(pl.offset.y(), pl.floor, 1e-12);
  EXPECT_NEAR(pl.offset.x(), 0.5 * (body.V.col(0).minCoeff() + body.V.col(0).maxCoeff()), 1e-12);
  const ProceduralBodyLandmarks lm = proceduralBodyLandmarks();
  EXPECT_NEAR(pl.offset.z(), lm.hip_z, 0.02);  // the torso's middle near hip height
  EXPECT_EQ(pl.scale, 1.0);
  BodyPlacementParams scaled;
  scaled.scale_to_height = true;
  EXPECT_NEAR(placementOnBody(body.V, scaled).scale, pl.body_height / kGarmentCodeBodyHeight, 1e-12);
  Pattern pat;
  pat.panels.resize(1);
  pat.panels[0].placement.pose.translation() = Eigen::Vector3d(0.1, 1.0, 0.2);
  applyPlacement(pl, pat);
  EXPECT_LT((pat.panels[0].placement.pose.translation() - (Eigen::Vector3d(0.1, 1.0, 0.2) + pl.offset)).norm(), 1e-12);
}

// Our own vests (test/data/garmentcode) on the procedural body, judged by the referee: plain, and
// with the front's side edges curved out to 33.7 cm sewn to the back's straight 30 cm (12% ease
// that the seams take in).
class GarmentCodeDrape : public ::testing::TestWithParam<const char*> {};

TEST_P(GarmentCodeDrape, VestOnTheProceduralBodyIsOnePieceWithItsOpenings) {
  Pattern pattern;
  GarmentCodeReport report;
  std::string err;
  DrapeParams params;
  GarmentCodeReadParams rp;
  rp.spacing = params.spacing;
  ASSERT_TRUE(readGarmentCodeJson(std::string(VIRTUAL_TRYON_SOURCE_DIR) + "/test/data/garmentcode/" + GetParam() +
                                      "_specification.json",
                                  rp, pattern, report, err))
      << err;
  EXPECT_EQ(pattern.name, GetParam());
  double takeIn = 0;
  for (const GarmentCodeStitch& s : report.stitches) takeIn = std::max(takeIn, std::abs(s.length_a - s.length_b));
  if (std::string(GetParam()) == "vest_eased") EXPECT_NEAR(takeIn, 0.0366, 0.001);
  const Body body(makeProceduralBody());
  const BodyPlacement placement = placePatternOnBody(body, pattern);
  EXPECT_GT(placement.lift.blocked_before, placement.lift.blocked_after) << placement.rule;
  TriMesh garment;
  const DrapeResult rep = drape(body, pattern, params, garment);
  ASSERT_TRUE(rep.success) << rep.message;
  EXPECT_TRUE(rep.converged) << rep.message;
  EXPECT_EQ(rep.seams_open, 0);
  EXPECT_LE(rep.strain_max_final, params.max_strain);
  // The drape report says what each seam took in: the reader's stitch lengths, seam by seam.
  ASSERT_EQ(rep.seam_lengths.size(), pattern.seams.size());
  EXPECT_NEAR(rep.seam_take_in_max, takeIn, 1e-3);  // sampled outlines: within a millimetre
  for (const DrapeResult::SeamLength& l : rep.seam_lengths) EXPECT_NEAR(l.take_in, std::abs(l.a - l.b), 1e-12);
  const ReferenceCounts c = ReferenceReferee(body.mesh()).count(garment);
  EXPECT_EQ(c.garment_edge_crossings, 0u);
  EXPECT_EQ(c.body_edge_crossings, 0u);
  EXPECT_EQ(c.vertices_inside, 0u);
  EXPECT_EQ(c.boundary_loops, 4u);  // neck, hem, two armholes
  EXPECT_EQ(rep.openings, 4u);
  // It hangs from the shoulders: its top is near the shoulders, not fallen to the hips.
  const ProceduralBodyLandmarks lm = proceduralBodyLandmarks();
  EXPECT_GT(garment.V.col(1).maxCoeff(), lm.chest_y);
}

INSTANTIATE_TEST_SUITE_P(Vests, GarmentCodeDrape, ::testing::Values("vest", "vest_eased"));

TEST(GarmentCodeCli, ConvertPatternWritesYamlThatReadsBack) {
  const std::string dir = tempDir("gc_cli");
  const std::string in = std::string(VIRTUAL_TRYON_SOURCE_DIR) + "/test/data/garmentcode/vest_specification.json";
  const CliRun run = runCli("convert-pattern --in " + in + " --out " + dir + "/vest.yaml", dir + "/err.txt");
  ASSERT_EQ(run.code, 0) << run.err;
  EXPECT_TRUE(contains(run.out, "\"openings\": 4")) << run.out;
  EXPECT_TRUE(contains(run.out, "\"take_in\"")) << run.out;
  Pattern fromYaml, fromJson;
  GarmentCodeReport r;
  std::string err;
  ASSERT_TRUE(readPatternYaml(dir + "/vest.yaml", fromYaml, err)) << err;
  ASSERT_TRUE(readGarmentCodeJson(in, GarmentCodeReadParams(), fromJson, r, err)) << err;
  ASSERT_EQ(fromYaml.panels.size(), fromJson.panels.size());
  EXPECT_EQ(fromYaml.seams.size(), fromJson.seams.size());
  for (std::size_t i = 0; i < fromJson.panels.size(); ++i)
    EXPECT_TRUE(fromYaml.panels[i].outline.isApprox(fromJson.panels[i].outline, 1e-12));
  // Bad input: exit 2, a message that names the place.
  std::ofstream(dir + "/bad.json") << with(squares(), R"({"panel": "back", "edge": 1})", R"({"panel": "sleeve", "edge": 1})");
  const CliRun bad = runCli("drape --body " + dir + "/none.obj --pattern " + dir + "/bad.json --out " + dir + "/o.obj",
                            dir + "/err2.txt");
  EXPECT_EQ(bad.code, 2);
  const CliRun badConvert = runCli("convert-pattern --in " + dir + "/bad.json --out " + dir + "/b.yaml", dir + "/err3.txt");
  EXPECT_EQ(badConvert.code, 2);
  EXPECT_TRUE(contains(badConvert.err, "no panel named 'sleeve'")) << badConvert.err;
  const CliRun badPlacement = runCli("convert-pattern --in " + in + " --out " + dir + "/c.yaml --placement '1 2'",
                                     dir + "/err4.txt");
  EXPECT_EQ(badPlacement.code, 2);
  EXPECT_TRUE(contains(badPlacement.err, "--placement")) << badPlacement.err;
}
