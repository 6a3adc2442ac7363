// `tryon`: the core without ROS, for batch use. See `tryon --help`.
// Exit codes: 0 converged / clean, 3 not converged / not clean, 2 bad input or usage.
#include "virtual_tryon/core/body.h"
#include "virtual_tryon/core/mesh_io.h"
#include "virtual_tryon/core/penetration_resolver.h"
#include "virtual_tryon/core/procedural.h"
#include "virtual_tryon/core/reference_check.h"
#include "virtual_tryon/core/report.h"

#include <sys/stat.h>

#include <cmath>
#include <cstdlib>
#include <exception>
#include <fstream>
#include <iostream>
#include <map>
#include <string>

namespace vt = virtual_tryon;

namespace {

const char* kUsage =
    "usage:\n"
    "  tryon resolve --body B --garment G --out OUT [--clearance M] [--max-iterations N]\n"
    "      Moves the garment out of the body (Sun et al. 2016). Prints the report as JSON.\n"
    "      Exit 0 converged, 3 not converged, 2 bad input.\n"
    "  tryon check --body B --garment G\n"
    "      Independent brute-force count of crossings (both directions) and inside vertices.\n"
    "      Exit 0 when all are zero, 3 otherwise.\n"
    "  tryon demo --out DIR\n"
    "      Resolves the built-in procedural scene; writes body.obj, garment_in.obj,\n"
    "      garment_out.obj and report.json into DIR.\n"
    "Meshes: OBJ, PLY or STL, metres, body faces wound counter-clockwise seen from outside.\n";

struct Usage : std::runtime_error {
  using std::runtime_error::runtime_error;
};

std::map<std::string, std::string> parseOptions(int argc, char** argv, int first) {
  std::map<std::string, std::string> opt;
  for (int i = first; i < argc; ++i) {
    const std::string a = argv[i];
    if (a.rfind("--", 0) != 0 || i + 1 >= argc) throw Usage("unexpected argument '" + a + "'");
    opt[a.substr(2)] = argv[++i];
  }
  return opt;
}

std::string required(const std::map<std::string, std::string>& opt, const std::string& key) {
  auto it = opt.find(key);
  if (it == opt.end()) throw Usage("missing --" + key);
  return it->second;
}

double number(const std::map<std::string, std::string>& opt, const std::string& key, double def) {
  auto it = opt.find(key);
  if (it == opt.end()) return def;
  char* end = nullptr;
  const double v = std::strtod(it->second.c_str(), &end);
  if (end == it->second.c_str() || *end != '\0' || !std::isfinite(v))
    throw Usage("--" + key + " needs a number, got '" + it->second + "'");
  return v;
}

vt::TriMesh load(const std::string& path, const std::string& what) {
  vt::TriMesh m;
  std::string err;
  if (!vt::readMesh(path, m, err)) throw std::invalid_argument(what + ": " + err);
  const vt::MeshValidation val = vt::validate(m, what);
  if (!val.ok) throw std::invalid_argument(val.message);
  if (!val.message.empty()) std::cerr << "warning: " << val.message << "\n";
  return m;
}

void save(const std::string& path, const vt::TriMesh& m) {
  std::string err;
  if (!vt::writeMesh(path, m, err)) throw std::runtime_error(err);
}

vt::ResolverParams resolverParams(const std::map<std::string, std::string>& opt) {
  vt::ResolverParams p;
  p.clearance = number(opt, "clearance", 0.0);
  const double it = number(opt, "max-iterations", p.max_iterations);
  if (it < 1 || it > 1e7) throw Usage("--max-iterations must be between 1 and 1e7");
  p.max_iterations = static_cast<int>(it);
  return p;
}

int resolve(const std::map<std::string, std::string>& opt) {
  const vt::TriMesh bodyMesh = load(required(opt, "body"), "body");
  vt::TriMesh garment = load(required(opt, "garment"), "garment");
  const std::string out = required(opt, "out");
  const vt::ResolverParams params = resolverParams(opt);
  vt::Body body(bodyMesh);
  const vt::ResolverReport rep = vt::resolvePenetrations(body, garment, params);
  save(out, garment);
  std::cout << vt::toJson(rep) << std::endl;
  return rep.converged ? 0 : 3;
}

int check(const std::map<std::string, std::string>& opt) {
  const vt::TriMesh body = load(required(opt, "body"), "body");
  const vt::TriMesh garment = load(required(opt, "garment"), "garment");
  const vt::ReferenceCounts c = vt::referenceCounts(body, garment, vt::edgeTopology(body).closed());
  std::cout << vt::toJson(c) << std::endl;
  return (c.garment_edge_crossings + c.body_edge_crossings + c.vertices_inside) == 0 ? 0 : 3;
}

int demo(const std::map<std::string, std::string>& opt) {
  const std::string dir = required(opt, "out");
  ::mkdir(dir.c_str(), 0755);
  vt::ResolveScene scene = vt::makeWrinkledTubeScene();
  save(dir + "/body.obj", scene.body);
  save(dir + "/garment_in.obj", scene.garment);
  vt::Body body(scene.body);
  const vt::ResolverReport rep = vt::resolvePenetrations(body, scene.garment);
  save(dir + "/garment_out.obj", scene.garment);
  const vt::ReferenceCounts c = vt::referenceCounts(scene.body, scene.garment);
  std::ofstream(dir + "/report.json") << "{\"resolver\": " << vt::toJson(rep)
                                      << ", \"independent_check\": " << vt::toJson(c) << "}\n";
  std::cout << vt::toJson(rep) << std::endl;
  return rep.converged ? 0 : 3;
}

}  // namespace

int main(int argc, char** argv) {
  try {
    if (argc < 2 || std::string(argv[1]) == "--help" || std::string(argv[1]) == "-h") {
      std::cout << kUsage;
      return argc < 2 ? 2 : 0;
    }
    const std::string cmd = argv[1];
    const auto opt = parseOptions(argc, argv, 2);
    if (cmd == "resolve") return resolve(opt);
    if (cmd == "check") return check(opt);
    if (cmd == "demo") return demo(opt);
    throw Usage("unknown command '" + cmd + "'");
  } catch (const Usage& e) {
    std::cerr << "tryon: " << e.what() << "\n" << kUsage;
    return 2;
  } catch (const std::exception& e) {
    std::cerr << "tryon: " << e.what() << "\n";
    return 2;
  }
}
