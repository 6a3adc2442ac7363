// The `tryon` command end to end: exit codes, JSON on stdout, vertex order of the output.
#include "test_helpers.h"
#include "virtual_tryon/core/io/mesh_io.h"
#include "virtual_tryon/core/drape/pattern.h"
#include "virtual_tryon/core/io/pattern_yaml.h"
#include "virtual_tryon/core/scenes/procedural.h"
#include "virtual_tryon/testing/reference_check.h"

#include <gtest/gtest.h>

#include <cstdio>
#include <fstream>
#include <iterator>
#include <string>

using namespace virtual_tryon;
using namespace virtual_tryon_test;

namespace {

// Writes body.obj (the capsule) and bag.yaml into a new directory; returns it.
std::string drapeScene() {
  const std::string dir = tempDir("tryon_cli_");
  std::string err;
  EXPECT_TRUE(writeMesh(dir + "/body.obj", makeCapsule(0.15, 0.6), err)) << err;
  std::ofstream(dir + "/bag.yaml") << bagPatternYaml();
  return dir;
}

}  // namespace

TEST(Cli, ResolveConvergesPrintsJsonAndKeepsVertexOrder) {
  const std::string dir = tempDir("tryon_cli_");
  ResolveScene s = makeWrinkledTubeScene(40, 24);
  save(dir + "/body.obj", s.body);
  save(dir + "/garment.ply", s.garment);  // mixed formats on purpose
  const CliRun r = runCli("resolve --body " + dir + "/body.obj --garment " + dir + "/garment.ply --out " + dir +
                          "/out.obj --clearance 0.002");
  EXPECT_EQ(r.code, 0) << r.out;
  EXPECT_EQ(r.out.front(), '{');
  EXPECT_NE(r.out.find("\"converged\": true"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("\"clearance_m\": 0.002"), std::string::npos) << r.out;
  TriMesh out;
  std::string err;
  ASSERT_TRUE(readMesh(dir + "/out.obj", out, err)) << err;
  ASSERT_EQ(out.V.rows(), s.garment.V.rows());
  EXPECT_EQ(out.F, s.garment.F);
  // Same order: every vertex moved by at most the deepest wrinkle plus clearance.
  EXPECT_LT((out.V - s.garment.V).rowwise().norm().maxCoeff(), 0.03);
  const ReferenceCounts c = referenceCounts(s.body, out);
  EXPECT_EQ(c.garment_edge_crossings + c.body_edge_crossings + c.vertices_inside, 0u);
  // The independent check agrees, through the CLI too.
  EXPECT_EQ(runCli("check --body " + dir + "/body.obj --garment " + dir + "/out.obj").code, 0);
  EXPECT_EQ(runCli("check --body " + dir + "/body.obj --garment " + dir + "/garment.ply").code, 3);
}

TEST(Cli, NotConvergedExitsThree) {
  const std::string dir = tempDir("tryon_cli_");
  save(dir + "/finger.stl", makeCylinder(0.01, 0.2, Eigen::Vector3d::Zero(), 16, 3, true));
  save(dir + "/patch.obj", makePatch(0.3, 0.3, 2, 2, Eigen::Vector3d(0.031, 0.0, -0.047)));
  const CliRun r = runCli("resolve --body " + dir + "/finger.stl --garment " + dir + "/patch.obj --out " + dir + "/o.obj");
  EXPECT_EQ(r.code, 3) << r.out;
  EXPECT_NE(r.out.find("\"converged\": false"), std::string::npos) << r.out;
}

TEST(Cli, BadInputExitsTwo) {
  const std::string dir = tempDir("tryon_cli_");
  save(dir + "/body.obj", makeSphere(0.1));
  EXPECT_EQ(runCli("resolve --body " + dir + "/missing.obj --garment " + dir + "/body.obj --out " + dir + "/o.obj").code, 2);
  EXPECT_EQ(runCli("resolve --body " + dir + "/body.obj --out " + dir + "/o.obj").code, 2);  // no --garment
  EXPECT_EQ(runCli("resolve --body " + dir + "/body.obj --garment " + dir + "/body.obj --out " + dir +
                   "/o.obj --max-iterations abc").code, 2);
  EXPECT_EQ(runCli("frobnicate").code, 2);
  const CliRun negative = runCli("resolve --body " + dir + "/body.obj --garment " + dir + "/body.obj --out " + dir +
                                     "/o.obj --body-uncertainty -0.001",
                                 dir + "/negative.err");
  EXPECT_EQ(negative.code, 2);
  EXPECT_NE(negative.err.find("--body-uncertainty must be >= 0"), std::string::npos) << negative.err;
  EXPECT_EQ(runCli("render --body " + dir + "/body.obj --garment " + dir + "/missing.obj --out " + dir + "/r").code, 2);
  std::ofstream(dir + "/nan.obj") << "v 0 0 0\nv 1 0 nan\nv 0 1 0\nf 1 2 3\n";
  EXPECT_EQ(runCli("resolve --body " + dir + "/body.obj --garment " + dir + "/nan.obj --out " + dir + "/o.obj").code, 2);
  EXPECT_EQ(runCli("--help").code, 0);
}

TEST(Cli, DrapeSettlesTheBagOnTheCapsulePrintsJsonAndWritesTheGarment) {
  const std::string dir = drapeScene();
  Pattern pattern;
  std::string err;
  ASSERT_TRUE(readPatternYaml(dir + "/bag.yaml", pattern, err)) << err;  // the test's own input is valid

  const CliRun r = runCli("drape --body " + dir + "/body.obj --pattern " + dir + "/bag.yaml --out " + dir +
                          "/bag.obj --spacing 0.03");
  EXPECT_EQ(r.code, 0) << r.out;
  ASSERT_FALSE(r.out.empty());
  EXPECT_EQ(r.out.front(), '{');
  EXPECT_EQ(r.out.find('\n'), r.out.size() - 1) << "one line of JSON";
  for (const char* key : {"\"success\": true", "\"converged\": true", "\"seams_total\": 3",
                          "\"seams_open\": 0", "\"resolver_run\": true", "\"resolver\": {\"converged\": true",
                          "\"penetrating_after\": 0", "\"dt_bound_s\": ", "\"warnings\": []"})
    EXPECT_TRUE(contains(r.out, key)) << key << " not in " << r.out;
  EXPECT_FALSE(contains(r.out, "\"map_size\": 0,")) << "image space is the default: maps were rendered";

  TriMesh garment;
  ASSERT_TRUE(readMesh(dir + "/bag.obj", garment, err)) << err;
  EXPECT_TRUE(contains(r.out, "\"vertices\": " + std::to_string(garment.numVertices()) + ",")) << r.out;
  EXPECT_GT(garment.numFaces(), 500);  // 2 panels of 20 x 10 quads at 3 cm
  // Resting on the cap (top of the capsule at y = 0.45), not fallen off, and nothing crosses it.
  const double top = garment.V.col(1).maxCoeff();
  EXPECT_GT(top, 0.45);
  EXPECT_LT(top, 0.50);
  const ReferenceCounts c = referenceCounts(makeCapsule(0.15, 0.6), garment);
  EXPECT_EQ(c.garment_edge_crossings, 0u);
  EXPECT_EQ(c.body_edge_crossings, 0u);
  EXPECT_EQ(c.vertices_inside, 0u);
}

TEST(Cli, DrapeOptionsReachTheCore) {
  const std::string dir = drapeScene();
  const std::string base = "drape --body " + dir + "/body.obj --pattern " + dir + "/bag.yaml --out " + dir + "/o.obj ";
  // No resolver pass: reported as not run.
  CliRun r = runCli(base + "--spacing 0.03 --no-resolve --mode image --tol 0.004 --map-size 128");
  EXPECT_TRUE(r.code == 0 || r.code == 3) << r.out;
  EXPECT_TRUE(contains(r.out, "\"resolver_run\": false")) << r.out;
  EXPECT_TRUE(contains(r.out, "\"resolver\": null")) << r.out;
  EXPECT_TRUE(contains(r.out, "\"map_size\": 130")) << r.out;  // 128 + the one-pixel margins
  // Too few iterations: not converged, exit 3, the garment is still written.
  std::remove((dir + "/o.obj").c_str());
  r = runCli(base + "--spacing 0.03 --max-iterations 20");
  EXPECT_EQ(r.code, 3) << r.out;
  EXPECT_TRUE(contains(r.out, "\"converged\": false")) << r.out;
  EXPECT_TRUE(contains(r.out, "\"iterations\": 20,")) << r.out;
  EXPECT_TRUE(contains(r.out, "iteration limit 20")) << r.out;
  EXPECT_TRUE(std::ifstream(dir + "/o.obj").good());
  // An explicit dt below the bound is used as given.
  r = runCli(base + "--spacing 0.03 --max-iterations 20 --dt 0.001");
  EXPECT_TRUE(contains(r.out, "\"dt_s\": 0.001,")) << r.out;
  // --friction reaches the collision response: the same short drape with the cloth kept still
  // against the bag (0) and sliding freely on it (1) ends in different places.
  r = runCli(base + "--spacing 0.03 --max-iterations 300 --friction 0");
  const std::string held = readText(dir + "/o.obj");
  r = runCli(base + "--spacing 0.03 --max-iterations 300 --friction 1");
  const std::string sliding = readText(dir + "/o.obj");
  EXPECT_FALSE(held.empty());
  EXPECT_NE(held, sliding);
}

TEST(Cli, DrapeBadInputExitsTwo) {
  const std::string dir = drapeScene();
  const std::string body = " --body " + dir + "/body.obj";
  const std::string out = " --out " + dir + "/o.obj";
  const std::string err = dir + "/stderr.txt";

  CliRun r = runCli("drape" + body + " --pattern " + dir + "/missing.yaml" + out, err);
  EXPECT_EQ(r.code, 2);
  EXPECT_TRUE(contains(readText(err), "missing.yaml")) << readText(err);

  std::ofstream(dir + "/broken.yaml") << "name: x\npanels:\n  - name: a\n    outline: [[0, 0], [1, 0]]\n";
  r = runCli("drape" + body + " --pattern " + dir + "/broken.yaml" + out, err);
  EXPECT_EQ(r.code, 2);
  EXPECT_TRUE(contains(readText(err), "broken.yaml")) << readText(err);

  // dt far above the eq. 4 bound: refused by the core, message on stderr names the bound.
  r = runCli("drape" + body + " --pattern " + dir + "/bag.yaml" + out + " --spacing 0.03 --dt 0.5", err);
  EXPECT_EQ(r.code, 2) << r.out;
  const std::string e = readText(err);
  EXPECT_TRUE(contains(e, "stability bound")) << e;
  EXPECT_TRUE(contains(e, "0.5")) << e;
  EXPECT_TRUE(contains(r.out, "\"success\": false")) << r.out;
  EXPECT_FALSE(std::ifstream(dir + "/o.obj").good()) << "no garment is written on failure";

  // Parameters out of range (core validateDrapeParams) and usage errors.
  r = runCli("drape" + body + " --pattern " + dir + "/bag.yaml" + out + " --tol -1", err);
  EXPECT_EQ(r.code, 2);
  EXPECT_TRUE(contains(readText(err), "tol")) << readText(err);
  EXPECT_EQ(runCli("drape" + body + " --pattern " + dir + "/bag.yaml" + out + " --mode mesh").code, 2);
  EXPECT_EQ(runCli("drape" + body + " --pattern " + dir + "/bag.yaml" + out + " --map-size 12.5").code, 2);
  EXPECT_EQ(runCli("drape" + body + " --pattern " + dir + "/bag.yaml" + out + " --spacing 0").code, 2);
  EXPECT_EQ(runCli("drape" + body + " --pattern " + dir + "/bag.yaml" + out + " --spaceing 0.03").code, 2);
  EXPECT_EQ(runCli("drape" + body + out).code, 2);  // no --pattern
  EXPECT_FALSE(std::ifstream(dir + "/o.obj").good());
}

namespace {

// The bytes of a file ("" when missing).
std::string fileBytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

}  // namespace

TEST(Cli, RenderWritesTheFitMapFromThreeSidesWithoutADisplay) {
#ifdef VIRTUAL_TRYON_SANITIZED
  GTEST_SKIP() << "OpenGL (Mesa under Xvfb) is not built with the sanitizers; the normal suite runs this";
#endif
  const std::string dir = tempDir("tryon_cli_");
  ResolveScene s = makeWrinkledTubeScene(40, 24);
  save(dir + "/body.obj", s.body);
  save(dir + "/garment.obj", s.garment);
  ASSERT_EQ(runCli("resolve --body " + dir + "/body.obj --garment " + dir + "/garment.obj --out " + dir + "/out.obj").code, 0);
  // No display: the command runs itself under xvfb-run.
  const std::string err = dir + "/render.err";
  const CliRun r = runCli("render --body " + dir + "/body.obj --garment " + dir + "/out.obj --reference " + dir +
                              "/garment.obj --out " + dir + "/fit --title tube",
                          err);
  ASSERT_EQ(r.code, 0) << r.err;
  std::string previous;
  for (const char* view : {"front", "side", "back"}) {
    const std::string png = fileBytes(dir + "/fit_" + view + ".png");
    ASSERT_GT(png.size(), 10000u) << view;
    EXPECT_EQ(png.substr(1, 3), "PNG") << view;
    EXPECT_NE(png, previous) << view << ": the same picture as the view before";
    previous = png;
    EXPECT_NE(r.err.find(std::string("fit_") + view + ".png"), std::string::npos) << r.err;
  }
  // A reference that is not the garment's input: bad input, nothing rendered.
  save(dir + "/other.obj", makePatch(0.1, 0.1, 3, 3));
  EXPECT_EQ(runCli("render --body " + dir + "/body.obj --garment " + dir + "/out.obj --reference " + dir +
                   "/other.obj --out " + dir + "/bad")
                .code,
            2);
  EXPECT_TRUE(fileBytes(dir + "/bad_front.png").empty());
}
