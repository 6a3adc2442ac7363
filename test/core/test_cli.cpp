// The `tryon` command end to end: exit codes, JSON on stdout, vertex order of the output.
#include "virtual_tryon/core/mesh_io.h"
#include "virtual_tryon/core/procedural.h"
#include "virtual_tryon/core/reference_check.h"

#include <gtest/gtest.h>

#include <sys/wait.h>

#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <string>

using namespace virtual_tryon;

namespace {

struct CliRun {
  int code = -1;
  std::string out;
};

CliRun run(const std::string& args) {
  CliRun r;
  const std::string cmd = std::string(VIRTUAL_TRYON_CLI) + " " + args + " 2>/dev/null";
  FILE* p = popen(cmd.c_str(), "r");
  if (!p) return r;
  char buf[4096];
  std::size_t n;
  while ((n = fread(buf, 1, sizeof buf, p)) > 0) r.out.append(buf, n);
  const int status = pclose(p);
  r.code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return r;
}

std::string tempDir() {
  std::string tmpl = ::testing::TempDir() + "tryon_cli_XXXXXX";
  char* d = mkdtemp(&tmpl[0]);
  return d ? std::string(d) : std::string("/tmp");
}

void save(const std::string& path, const TriMesh& m) {
  std::string err;
  ASSERT_TRUE(writeMesh(path, m, err)) << err;
}

}  // namespace

TEST(Cli, ResolveConvergesPrintsJsonAndKeepsVertexOrder) {
  const std::string dir = tempDir();
  ResolveScene s = makeWrinkledTubeScene(40, 24);
  save(dir + "/body.obj", s.body);
  save(dir + "/garment.ply", s.garment);  // mixed formats on purpose
  const CliRun r = run("resolve --body " + dir + "/body.obj --garment " + dir + "/garment.ply --out " + dir +
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
  EXPECT_EQ(run("check --body " + dir + "/body.obj --garment " + dir + "/out.obj").code, 0);
  EXPECT_EQ(run("check --body " + dir + "/body.obj --garment " + dir + "/garment.ply").code, 3);
}

TEST(Cli, NotConvergedExitsThree) {
  const std::string dir = tempDir();
  save(dir + "/finger.stl", makeCylinder(0.01, 0.2, Eigen::Vector3d::Zero(), 16, 3, true));
  save(dir + "/patch.obj", makePatch(0.3, 0.3, 2, 2, Eigen::Vector3d(0.031, 0.0, -0.047)));
  const CliRun r = run("resolve --body " + dir + "/finger.stl --garment " + dir + "/patch.obj --out " + dir + "/o.obj");
  EXPECT_EQ(r.code, 3) << r.out;
  EXPECT_NE(r.out.find("\"converged\": false"), std::string::npos) << r.out;
}

TEST(Cli, BadInputExitsTwo) {
  const std::string dir = tempDir();
  save(dir + "/body.obj", makeSphere(0.1));
  EXPECT_EQ(run("resolve --body " + dir + "/missing.obj --garment " + dir + "/body.obj --out " + dir + "/o.obj").code, 2);
  EXPECT_EQ(run("resolve --body " + dir + "/body.obj --out " + dir + "/o.obj").code, 2);  // no --garment
  EXPECT_EQ(run("resolve --body " + dir + "/body.obj --garment " + dir + "/body.obj --out " + dir +
                "/o.obj --max-iterations abc").code, 2);
  EXPECT_EQ(run("frobnicate").code, 2);
  std::ofstream(dir + "/nan.obj") << "v 0 0 0\nv 1 0 nan\nv 0 1 0\nf 1 2 3\n";
  EXPECT_EQ(run("resolve --body " + dir + "/body.obj --garment " + dir + "/nan.obj --out " + dir + "/o.obj").code, 2);
  EXPECT_EQ(run("--help").code, 0);
}
