// Shared by the core suites: text and file helpers, the `tryon` command run as a user runs it
// (cli_test, malformed_cli_test), the bag pattern both of those drape, and hand-made stencils
// (impact_zones_test, resolver_options_test). Everything is inline: core_tests is one binary of
// every test/core/*_test.cpp.
#pragma once

#include "virtual_tryon/core/geometry/mesh.h"
#include "virtual_tryon/core/io/mesh_io.h"
#include "virtual_tryon/core/resolve/stencils.h"

#include <gtest/gtest.h>

#include <sys/wait.h>

#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <string>

namespace virtual_tryon_test {

namespace vt = virtual_tryon;

inline bool contains(const std::string& s, const std::string& part) { return s.find(part) != std::string::npos; }

// The whole file as it is on disk; empty when it cannot be read.
inline std::string readText(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

// A new directory under gtest's temporary directory, named `prefix` and six random characters.
inline std::string tempDir(const std::string& prefix) {
  std::string tmpl = ::testing::TempDir() + prefix + "XXXXXX";
  char* d = mkdtemp(&tmpl[0]);
  return d ? std::string(d) : std::string("/tmp");
}

// Writes `m` to `path` (format by extension); a fatal failure of the calling test when it cannot.
inline void save(const std::string& path, const vt::TriMesh& m) {
  std::string err;
  ASSERT_TRUE(vt::writeMesh(path, m, err)) << err;
}

// ---------------------------------------------------------------------------------------------
// The `tryon` command (VIRTUAL_TRYON_CLI, given by CMake).

struct CliRun {
  int code = -1;    // exit code; -1 when it could not be started or did not exit normally
  std::string out;  // stdout
  std::string err;  // stderr, read back from errFile
};

// Runs `tryon ARGS` through the shell: stdout into out, stderr into the file `errFile` and from
// there into err (default: discarded).
inline CliRun runCli(const std::string& args, const std::string& errFile = "/dev/null") {
  CliRun r;
  const std::string cmd = std::string(VIRTUAL_TRYON_CLI) + " " + args + " 2>" + errFile;
  FILE* p = popen(cmd.c_str(), "r");
  if (!p) return r;
  char buf[4096];
  std::size_t n;
  while ((n = fread(buf, 1, sizeof buf, p)) > 0) r.out.append(buf, n);
  const int status = pclose(p);
  r.code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  r.err = readText(errFile);
  return r;
}

// A bag over the top of a capsule (radius 0.15 m, 0.6 m cylinder along y, top at y = 0.45 m), as
// YAML: two 0.6 x 0.3 m panels wrapped half a turn each on a 0.2 m cylinder about y (front facing
// +z, back turned half a turn), hem at y = 0.25 m with the default translation, sewn along both
// sides and across the top. The sewn top rests on the capsule's cap, so the cloth settles.
inline std::string bagPatternYaml(const std::string& translation = "[0, 0.25, 0]") {
  return "name: bag\npanels:\n"
         "  - name: front\n    outline: [[-0.3, 0.0], [0.3, 0.0], [0.3, 0.3], [-0.3, 0.3]]\n"
         "    placement: {translation: " + translation + ", wrap_radius: 0.2}\n"
         "  - name: back\n    outline: [[-0.3, 0.0], [0.3, 0.0], [0.3, 0.3], [-0.3, 0.3]]\n"
         "    placement: {translation: " + translation + ", rotation_rpy: [0, 3.141592653589793, 0], wrap_radius: 0.2}\n"
         "seams:\n"
         "  - a: {panel: front, from: 1, to: 2}\n    b: {panel: back, from: 0, to: 3}\n"
         "  - a: {panel: front, from: 0, to: 3}\n    b: {panel: back, from: 1, to: 2}\n"
         "  - a: {panel: front, from: 2, to: 3}\n    b: {panel: back, from: 3, to: 2}\n";
}

// ---------------------------------------------------------------------------------------------
// Stencils.

// A vertex-face stencil on garment vertex v: gradient along n (normalised), constraint value D.
inline vt::Stencil vertexStencil(int v, const Eigen::Vector3d& n, double D) {
  vt::Stencil s;
  s.count = 1;
  s.vertex = {{v, -1, -1}};
  s.weight = {{1, 0, 0}};
  s.normal = n.normalized();
  s.D = D;
  return s;
}

}  // namespace virtual_tryon_test
