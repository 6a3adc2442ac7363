// `tryon`: the core without ROS, for batch use. See `tryon --help`.
// Exit codes: 0 converged / clean, 3 not converged / not clean, 2 bad input or usage.
#include "virtual_tryon/core/body/body.h"
#include "virtual_tryon/core/body/body_preparation.h"
#include "virtual_tryon/core/drape/drape.h"
#include "virtual_tryon/core/drape/frames_ahead.h"
#include "virtual_tryon/core/drape/worn_garment.h"
#include "virtual_tryon/core/io/json_object.h"
#include "virtual_tryon/core/io/mesh_io.h"
#include "virtual_tryon/core/drape/pattern.h"
#include "virtual_tryon/core/io/pattern_garmentcode.h"
#include "virtual_tryon/core/io/point_cache.h"
#include "virtual_tryon/core/io/pattern_yaml.h"
#include "virtual_tryon/core/drape/pattern_placement.h"
#include "virtual_tryon/core/drape/pattern_transform.h"
#include "virtual_tryon/core/resolve/penetration_resolver.h"
#include "virtual_tryon/core/resolve/temporal_coherence.h"
#include "virtual_tryon/core/scenes/procedural.h"
#include "virtual_tryon/testing/reference_bvh.h"
#include "virtual_tryon/testing/reference_check.h"
#include "virtual_tryon/testing/reference_shape.h"
#include "virtual_tryon/core/io/report.h"
#include "virtual_tryon/render/fit_render.h"
#include "virtual_tryon/heap_settings.h"

#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <exception>
#include <fstream>
#include <iostream>
#include <map>
#include <numeric>
#include <memory>
#include <set>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

namespace vt = virtual_tryon;

namespace {

// The usage text; the drape defaults come from the core's DrapeParams.
std::string usage() {
  const vt::DrapeParams d;
  auto g = [](double v) {
    std::ostringstream o;
    o << v;
    return o.str();
  };
  const vt::MeshLimits limits;
  return "usage:\n"
         "  tryon resolve --body B --garment G --out OUT [--clearance M] [--body-uncertainty M]\n"
         "                [--max-iterations N] [--objective smooth|paper]\n"
         "      Moves the garment out of the body (Sun et al. 2016). Prints the report as JSON,\n"
         "      with the edge strain and displacement it produced. --objective smooth (default):\n"
         "      the paper's rounds, then a shape relaxation that keeps every constraint; paper:\n"
         "      the rounds alone. --body-uncertainty: how far the true surface may lie outside\n"
         "      the body mesh (a scan's error, m; default 0): the garment clears the mesh by the\n"
         "      clearance plus this. Exit 0 converged, 3 not converged, 2 bad input.\n"
         "  tryon check --body B --garment G [--reference INPUT]\n"
         "      Independent brute-force count of crossings (both directions) and inside vertices.\n"
         "      With --reference (the garment before it was resolved): also its shape against\n"
         "      INPUT (edge strain max / p99, displacement, the need, far vertices moved).\n"
         "      Exit 0 when all counts are zero, 3 otherwise.\n"
         "  tryon drape --body B --pattern P.yaml --out OUT [--spacing M] [--mode image|object]\n"
         "              [--dt S] [--max-iterations N] [--no-resolve] [--tol M] [--friction F] [--map-size N]\n"
         "              [--density KG_M2] [--k-structural K] [--k-shear K] [--k-flexion K]\n"
         "              [--max-strain S] [--body-uncertainty M] [--render PREFIX]\n"
         "      Sews and drapes the garment given by the cutting patterns P.yaml\n"
         "      (config/patterns/README.md) on the body (Vassilev et al. 2001), then resolves\n"
         "      what penetrates (Sun et al. 2016) unless --no-resolve.\n"
         "      P may also be a GarmentCode pattern specification (.json, or any file whose\n"
         "      content is a JSON object; README, GarmentCode patterns): its curves are sampled\n"
         "      at the spacing and its panels placed on the body by the placement rule:\n"
         "      --placement    auto (default: its floor to the body's lowest point, x and z to the\n"
         "                     torso centre at hip height), none (GarmentCode's own frame), or\n"
         "                     'TX TY TZ [RX RY RZ]': this transform from GarmentCode's frame (m,\n"
         "                     Euler degrees, R = Rz Ry Rx) instead of the rule\n"
         "      --scale-to-height  with auto: also scale the panel positions by the body's\n"
         "                     height / 1.72 m\n"
         "      --spacing      cloth grid spacing, m (default " + g(d.spacing) + ")\n"
         "      --mode         collisions: image (depth maps, default) or object (body mesh)\n"
         "      --dt           time step, s (default: " + g(d.dt_safety) + " x the stability bound;\n"
         "                     a dt above the bound is refused)\n"
         "      --max-iterations  sewing + draping iterations (default " + g(d.max_iterations) + ")\n"
         "      --tol          collision tolerance, m (default " + g(d.collision.tol) + ")\n"
         "      --friction     kept fraction of the tangential velocity in a collision, 0 .. 1\n"
         "                     (default " + g(d.collision.friction) + ")\n"
         "      --map-size     depth map pixels along the longer side (default 0: one pixel = tol;\n"
         "                     else 16 .. 4096)\n"
         "      --density      cloth density, kg/m^2 (default " + g(d.cloth.density) + ")\n"
         "      --k-structural, --k-shear, --k-flexion  spring stiffnesses, N/m (default " +
         g(d.cloth.k_structural) + ", " + g(d.cloth.k_shear) + ", " + g(d.cloth.k_flexion) + ")\n"
         "      --max-strain   a spring of the returned garment longer than (1 + S) x its rest\n"
         "                     length makes the drape not converged (default " + g(d.max_strain) + "; 0: no limit)\n"
         "      Prints the report as JSON and writes the garment (one welded mesh) to OUT.\n"
         "      Exit 0 converged, 3 not converged, 2 bad input or a failed drape (message on\n"
         "      stderr; no OUT written).\n"
         "  tryon convert-pattern --in P.json --out P.yaml [--spacing M] [--body B]\n"
         "                [--placement ...] [--scale-to-height]\n"
         "      Writes a GarmentCode pattern specification as our YAML pattern: curves sampled at\n"
         "      the spacing (default " + g(d.spacing) + "), panels in GarmentCode's frame (metres), or placed\n"
         "      on the body B as drape does. Prints the stitches (lengths, take-in) as JSON.\n"
         "  tryon render --body B --garment G --out PREFIX [--reference INPUT] [--strain-scale S]\n"
         "               [--title T]\n"
         "      Writes PREFIX_front.png, PREFIX_side.png, PREFIX_back.png (VTK, offscreen): the body\n"
         "      in grey, the garment coloured by edge strain against INPUT (the garment before it\n"
         "      was resolved: same faces and vertex order; blue 0 .. red S and beyond, default\n"
         "      0.15), in one colour without INPUT. Without an X display it runs itself under\n"
         "      xvfb-run. drape --render PREFIX writes the same pictures of a drape, coloured by\n"
         "      the strain of its structural springs.\n"
         "  tryon animate resolve --body B.obj --body-cache B.pc2 --garment G.obj --garment-cache G.pc2\n"
         "                --out OUT.pc2 [--check] [--max-jitter M] [--cold] [--warm-min M] [--clearance M]\n"
         "                [--max-iterations N] [--objective ...] [--no-backward]\n"
         "      Resolves every frame of an animated garment on an animated body (Point Cache 2, in\n"
         "      the rest meshes' vertex order; Sun et al. 2016's garment animation synthesis).\n"
         "      Each frame on its own (history-free). One JSON line per frame (crossings before\n"
         "      and after, inside, iterations, displacement, strain, jitter: the largest change of\n"
         "      a vertex's correction from the frame before, milliseconds; ms_body_tree: the body\n"
         "      tree's build on frame 0, its refit after), then a summary line.\n"
         "      --check adds the referee's counts per frame. Each frame starts from its input moved by\n"
         "      the previous frame's correction (a warm start: still resolved and checked whole, its\n"
         "      shape kept against its own input; a warm frame that does not converge is resolved\n"
         "      again from its input); --cold resolves every frame from its input alone.\n"
         "      A warm frame is relaxed locally: round the vertices its rounds moved and the edges\n"
         "      its start strains past 0.1, 3 rings; where that leaves an edge strained past\n"
         "      --widen-strain S (default 0.25) against the input, over every moved vertex again.\n"
         "      --full-relaxation: always over every moved vertex.\n"
         "      --warm-min M (default 0; " + g(vt::kWarmStartMinCorrection) + " with --full-relaxation): only\n"
         "      corrections of at least M are carried over (the full relaxation would spread the\n"
         "      smaller ones further every frame).\n"
         "      --max-jitter M (default 0.003, 0: off): after a frame is resolved, each vertex whose\n"
         "      correction changed by more than M moves towards its previous correction, to a\n"
         "      change of M, where that keeps the frame clean (no crossing, not inside, clear of\n"
         "      the body) and its edges within strain 0.3 (or their strain as resolved, if more);\n"
         "      \"coherence\" in its line says how many were over and how many stayed.\n"
         "      Then a backward pass (--no-backward: none): from the last frame but one back to the\n"
         "      first, each vertex whose correction still differs by more than M from the next\n"
         "      frame's moves towards it, where that keeps its own frame clean, so that a jump the\n"
         "      body forced on a later frame is spread over the frames before it; one\n"
         "      {\"backward_frame\": K, ...} line per frame it moved (with --check, the referee's\n"
         "      counts again). The summary's jitter_max_m is after both passes,\n"
         "      jitter_max_forward_m after the first alone.\n"
         "      Writes the resolved frames to OUT.pc2.\n"
         "      Exit 0 when every frame converged, 3 otherwise, 2 on bad input.\n"
         "  tryon animate drape --body B.obj --body-cache B.pc2 --pattern P --out OUT[.pc2] [--check]\n"
         "                [--fps F] [--frames N] [--cloth-dt S] [--strain-restore R] [--no-body-velocity]\n"
         "                [--no-interpolate] [--no-skin-velocity] [--no-top-view] [--side-view]\n"
         "                [--relax-compression C] [--no-resolve-relaxed] [--no-carry] [--sequential]\n"
         "                [--frames-ahead N] [--quick-sweeps N] [drape options]\n"
         "      Drapes the pattern on the body cache's first frame (as tryon drape, with its\n"
         "      options), then wears it through the motion: per frame (1 / F s, default F 30) the\n"
         "      cloth steps (--cloth-dt, default " + g(vt::WornGarmentParams().dt_safety) + " x the explicit step's stability limit\n"
         "      for the cloth as draped, 2 / sqrt(largest eigenvalue of M^-1 K), at least the\n"
         "      drape's step; frame 0's line gives both) against the body interpolated\n"
         "      between the two frames' depth maps, responding to the surface's velocity, and Sun\n"
         "      et al.'s resolver corrects what is left inside. --strain-restore: the fraction of a\n"
         "      spring's excess over the super-elastic threshold taken back per step (default " +
         g(vt::WornGarmentParams().strain_restore) + "). --no-skin-velocity: the surface's speed along\n"
         "      its normal alone (from the change of depth), not the body vertices' velocity.\n"
         "      --no-top-view: without the maps seen from above (the paper's front and back maps\n"
         "      alone); --side-view: with maps seen from the side too. A frame whose corrected cloth\n"
         "      is strained past max_strain has its springs relaxed (stretched ones back to 1 +\n"
         "      stretch threshold, squeezed ones out to 1 - C, default " + g(vt::WornGarmentParams().relax_compression) + ", 0: stretched alone) and\n"
         "      is resolved again, and that is kept when it converges and is less strained;\n"
         "      --no-resolve-relaxed: the first correction. Where the steps left no spring\n"
         "      strained past " + g(vt::WornGarmentParams().quick_strain) + ", the correction first relaxes the shape in --quick-sweeps sweeps\n"
         "      (default " + std::to_string(vt::WornGarmentParams().quick_sweeps) + ", over " + std::to_string(vt::WornGarmentParams().quick_rings) + " rings round what it moved), kept when no spring ends\n"
         "      past " + g(vt::WornGarmentParams().quick_strain) + "; otherwise the frame is corrected with the drape's relaxation (0:\n"
         "      always that one; the skin-carried fallback always uses it).\n"
         "      The next frames' body refits and maps are made on a second thread while the cloth\n"
         "      steps through frame k, at most --frames-ahead N of them waiting (default " + std::to_string(vt::FramesAhead::kDefaultDepth) + "),\n"
         "      the first ones while frame 0 is draped (--sequential: one after the other; the same\n"
         "      results); a frame's ms is the wall time since the frame before\n"
         "      (frame 1: the drape) was timed (the referee's count left out).\n"
         "      One JSON line per frame (steps, strain, crossings, milliseconds; --check adds the\n"
         "      referee's counts), then a summary. Writes OUT.obj (the garment on\n"
         "      frame 0) and OUT.pc2 (every frame). Exit 0 when every frame converged, 3 when one\n"
         "      did not or the cloth blew up (the frames before are written), 2 on bad input.\n"
         "  tryon demo --out DIR\n"
         "      Resolves the built-in procedural scene; writes body.obj, garment_in.obj,\n"
         "      garment_out.obj and report.json into DIR.\n"
         "Meshes: OBJ, PLY or STL, metres, body faces wound counter-clockwise seen from outside.\n"
         "Every command that reads meshes takes [--max-vertices N] [--max-faces N]: larger meshes\n"
         "are refused before they are read (default " + std::to_string(limits.max_vertices) + " and " +
         std::to_string(limits.max_faces) + "; the cloth of a drape is held to --max-vertices too).\n"
         "Warnings about the input (degenerate or duplicate faces, an open or non-manifold body,\n"
         "a size that suggests millimetres, meshes far apart) go to stderr as 'warning: ...'.\n";
}

struct Usage : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// Options without a value.
const std::set<std::string> kFlags = {"no-resolve", "scale-to-height", "check", "warm-start", "cold", "no-body-velocity",
                                      "no-top-view", "side-view", "no-interpolate", "no-skin-velocity",
                                      "no-resolve-relaxed", "no-carry", "sequential", "no-backward", "full-relaxation"};

std::map<std::string, std::string> parseOptions(int argc, char** argv, int first) {
  std::map<std::string, std::string> opt;
  for (int i = first; i < argc; ++i) {
    const std::string a = argv[i];
    if (a.rfind("--", 0) != 0) throw Usage("unexpected argument '" + a + "'");
    const std::string key = a.substr(2);
    if (kFlags.count(key)) {
      opt[key] = "";
      continue;
    }
    if (i + 1 >= argc) throw Usage("--" + key + " needs a value");
    opt[key] = argv[++i];
  }
  return opt;
}

// Refuses options the command does not know (a typo would otherwise be silently ignored).
void allowOnly(const std::map<std::string, std::string>& opt, const std::string& cmd,
               const std::set<std::string>& known) {
  for (const auto& kv : opt)
    if (!known.count(kv.first)) throw Usage("'" + cmd + "' has no option --" + kv.first);
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

// An integer option in [lo, hi].
int integer(const std::map<std::string, std::string>& opt, const std::string& key, int def, int lo,
            int hi) {
  const double v = number(opt, key, def);
  if (v != std::floor(v) || v < lo || v > hi)
    throw Usage("--" + key + " must be an integer between " + std::to_string(lo) + " and " +
                std::to_string(hi) + ", got '" + opt.at(key) + "'");
  return static_cast<int>(v);
}

void warn(const std::string& w) { std::cerr << "warning: " << w << "\n"; }

vt::MeshLimits meshLimits(const std::map<std::string, std::string>& opt) {
  vt::MeshLimits l;
  l.max_vertices = static_cast<std::size_t>(integer(opt, "max-vertices", static_cast<int>(l.max_vertices), 1, 1000000000));
  l.max_faces = static_cast<std::size_t>(integer(opt, "max-faces", static_cast<int>(l.max_faces), 1, 1000000000));
  return l;
}

// Reads a mesh file; `what` ("body", "garment") names it in the error and the warning about
// dropped polygons.
vt::TriMesh readMeshFile(const std::string& path, const std::string& what, const vt::MeshLimits& limits) {
  vt::TriMesh m;
  std::string err;
  vt::MeshReadInfo info;
  if (!vt::readMesh(path, m, err, &info, limits)) throw std::invalid_argument(what + ": " + err);
  if (info.polygons_dropped > 0)
    warn(what + ": " + std::to_string(info.polygons_dropped) + " of " + std::to_string(info.polygons_read) +
         " polygons have fewer than 3 vertices and were dropped");
  return m;
}

// Reads and checks a garment (validate); warnings go to stderr.
vt::TriMesh loadGarment(const std::string& path, const vt::MeshLimits& limits) {
  vt::TriMesh m = readMeshFile(path, "garment", limits);
  const vt::MeshValidation val = vt::validate(m, "garment", limits);
  if (!val.ok) throw std::invalid_argument(val.message);
  for (const std::string& w : val.warnings) warn(w);
  return m;
}

// Reads and prepares the body (prepareBody; an inside-out body is refused, not flipped); warnings
// go to stderr.
vt::BodyPreparation loadBody(const std::string& path, const vt::MeshLimits& limits) {
  vt::BodyPreparationParams params;
  params.limits = limits;
  params.policy = vt::InsideOutPolicy::Refuse;
  vt::BodyPreparation body = vt::prepareBody(readMeshFile(path, "body", limits), params);
  if (!body.ok) throw std::invalid_argument(body.error);
  for (const std::string& w : body.warnings) warn(w);
  return body;
}

void save(const std::string& path, const vt::TriMesh& m) {
  std::string err;
  if (!vt::writeMesh(path, m, err)) throw std::runtime_error(err);
}

vt::ResolverParams resolverParams(const std::map<std::string, std::string>& opt) {
  vt::ResolverParams p;
  p.clearance = number(opt, "clearance", 0.0);
  p.body_uncertainty = number(opt, "body-uncertainty", 0.0);
  if (p.body_uncertainty < 0) throw Usage("--body-uncertainty must be >= 0 (metres)");
  const double it = number(opt, "max-iterations", p.max_iterations);
  if (it < 1 || it > 1e7) throw Usage("--max-iterations must be between 1 and 1e7");
  p.max_iterations = static_cast<int>(it);
  if (opt.count("objective")) {
    const std::string& o = opt.at("objective");
    if (o == "smooth")
      p.objective = vt::ResolverObjective::Smooth;
    else if (o == "paper")
      p.objective = vt::ResolverObjective::Paper;
    else
      throw Usage("--objective must be 'smooth' or 'paper', got '" + o + "'");
  }
  return p;
}

int resolve(const std::map<std::string, std::string>& opt) {
  const std::string bodyPath = required(opt, "body"), garmentPath = required(opt, "garment");
  const std::string out = required(opt, "out");
  const vt::ResolverParams params = resolverParams(opt);
  const vt::MeshLimits limits = meshLimits(opt);
  vt::BodyPreparation prepared = loadBody(bodyPath, limits);
  vt::TriMesh garment = loadGarment(garmentPath, limits);
  for (const std::string& w : vt::placementWarnings(prepared.mesh, garment)) warn(w);
  vt::Body body(std::move(prepared.mesh));
  const vt::ResolverReport rep = vt::resolvePenetrations(body, garment, params);
  save(out, garment);
  std::cout << vt::toJson(rep) << std::endl;
  return rep.converged ? 0 : 3;
}

int check(const std::map<std::string, std::string>& opt) {
  const vt::MeshLimits limits = meshLimits(opt);
  const vt::BodyPreparation body = loadBody(required(opt, "body"), limits);
  const vt::TriMesh garment = loadGarment(required(opt, "garment"), limits);
  const vt::ReferenceCounts c = vt::referenceCounts(body.mesh, garment, body.check.closed);
  if (!opt.count("reference")) {
    std::cout << vt::toJson(c) << std::endl;
  } else {
    const vt::TriMesh input = loadGarment(opt.at("reference"), limits);
    if (input.V.rows() != garment.V.rows() || input.F.rows() != garment.F.rows() || input.F != garment.F)
      throw std::invalid_argument("--reference " + opt.at("reference") + ": " + std::to_string(input.V.rows()) +
                                  " vertices / " + std::to_string(input.F.rows()) +
                                  " faces, not the garment's faces and vertex order (" +
                                  std::to_string(garment.V.rows()) + " / " + std::to_string(garment.F.rows()) + ")");
    const vt::ReferenceShape shape =
        vt::referenceShape(vt::ReferenceReferee(body.mesh), input, garment, body.check.closed);
    std::cout << "{\"counts\": " << vt::toJson(c) << ", \"shape\": " << vt::toJson(shape) << "}" << std::endl;
  }
  return (c.garment_edge_crossings + c.body_edge_crossings + c.vertices_inside) == 0 ? 0 : 3;
}

// The fit-map pictures; throws when they cannot be made.
void renderPictures(const vt::TriMesh& body, const vt::TriMesh& garment, const std::vector<double>& strain,
                    const std::string& prefix, const std::map<std::string, std::string>& opt, const std::string& title) {
  vt::FitRenderParams p;
  p.strain_scale = number(opt, "strain-scale", p.strain_scale);
  p.title = opt.count("title") ? opt.at("title") : title;
  const vt::FitRenderResult r = vt::renderFit(body, garment, strain, prefix, p);
  if (!r.success) throw std::invalid_argument("render: " + r.message);
  for (const std::string& f : r.files) std::cerr << "tryon: wrote " << f << "\n";
}

// The name of a file without its folder and extension.
std::string stem(const std::string& path) {
  const std::size_t slash = path.find_last_of('/');
  std::string name = slash == std::string::npos ? path : path.substr(slash + 1);
  const std::size_t dot = name.find_last_of('.');
  return dot == std::string::npos ? name : name.substr(0, dot);
}

// --placement 'TX TY TZ [RX RY RZ]': metres and Euler degrees (R = Rz Ry Rx, GarmentCode's order).
Eigen::Isometry3d explicitPlacement(const std::string& text) {
  std::istringstream in(text);
  std::vector<double> v;
  double x = 0;
  while (in >> x) v.push_back(x);
  if (!in.eof() || (v.size() != 3 && v.size() != 6) ||
      std::any_of(v.begin(), v.end(), [](double a) { return !std::isfinite(a); }))
    throw Usage("--placement must be auto, none, or 'TX TY TZ [RX RY RZ]' (metres, degrees), got '" + text + "'");
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.translation() = Eigen::Vector3d(v[0], v[1], v[2]);
  if (v.size() == 6) T.linear() = vt::garmentCodeRotation(Eigen::Vector3d(v[3], v[4], v[5]));
  return T;
}

bool isGarmentCodeFile(const std::string& path) {
  if (path.size() >= 5 && path.compare(path.size() - 5, 5, ".json") == 0) return true;
  std::ifstream in(path);
  std::string head(256, '\0');
  in.read(&head[0], static_cast<std::streamsize>(head.size()));
  head.resize(static_cast<std::size_t>(std::max<std::streamsize>(0, in.gcount())));
  return vt::looksLikeJson(head);
}

// The stitches of a GarmentCode pattern as JSON: lengths and what each seam takes in.
std::string stitchesJson(const vt::GarmentCodeReport& rep) {
  std::string out = "[";
  for (std::size_t i = 0; i < rep.stitches.size(); ++i) {
    const vt::GarmentCodeStitch& s = rep.stitches[i];
    out += (i ? ", " : "") + vt::json::Obj()
                                 .add("a", s.panel_a + ":" + std::to_string(s.edge_a))
                                 .add("b", s.panel_b + ":" + std::to_string(s.edge_b))
                                 .add("length_a", s.length_a)
                                 .add("length_b", s.length_b)
                                 .add("take_in", std::abs(s.length_a - s.length_b))
                                 .add("seams", s.seams.size())
                                 .str();
  }
  return out + "]";
}

// Reads a YAML pattern, or a GarmentCode specification (sampled at `spacing`) placed on the body
// (nullptr: left in GarmentCode's frame unless --placement gives a transform).
vt::Pattern loadPattern(const std::string& path, double spacing, const vt::Body* body,
                        const std::map<std::string, std::string>& opt, vt::GarmentCodeReport* report = nullptr) {
  vt::Pattern pattern;
  std::string err;
  if (!isGarmentCodeFile(path)) {
    if (opt.count("placement") || opt.count("scale-to-height"))
      throw Usage("--placement and --scale-to-height are for GarmentCode patterns (.json)");
    if (!vt::readPatternYaml(path, pattern, err)) throw std::invalid_argument(err);
    return pattern;
  }
  vt::GarmentCodeReadParams rp;
  rp.spacing = spacing;
  vt::GarmentCodeReport rep;
  if (!vt::readGarmentCodeJson(path, rp, pattern, rep, err)) throw std::invalid_argument(err);
  for (const std::string& w : rep.warnings) warn(w);
  const std::string mode = opt.count("placement") ? opt.at("placement") : (body ? "auto" : "none");
  if (mode == "auto") {
    if (!body) throw Usage("--placement auto needs --body");
    vt::BodyPlacementParams bp;
    bp.scale_to_height = opt.count("scale-to-height") > 0;
    const vt::BodyPlacement placement = vt::placePatternOnBody(*body, pattern, bp);
    std::cerr << "tryon: placement: " << placement.rule << "\n";
  } else if (mode != "none") {
    if (opt.count("scale-to-height")) throw Usage("--scale-to-height goes with --placement auto");
    vt::transformPattern(explicitPlacement(mode), pattern);
  }
  if (report) *report = rep;
  return pattern;
}

int convertPattern(const std::map<std::string, std::string>& opt) {
  const std::string in = required(opt, "in"), out = required(opt, "out");
  const double spacing = number(opt, "spacing", vt::DrapeParams().spacing);
  if (!(spacing > 0)) throw Usage("--spacing must be > 0 (metres)");
  if (!isGarmentCodeFile(in)) throw std::invalid_argument(in + ": not a GarmentCode pattern specification (JSON)");
  std::unique_ptr<vt::Body> body;
  if (opt.count("body")) body = std::make_unique<vt::Body>(loadBody(opt.at("body"), meshLimits(opt)).mesh);
  vt::GarmentCodeReport rep;
  const vt::Pattern pattern = loadPattern(in, spacing, body.get(), opt, &rep);
  std::ofstream f(out);
  f << vt::patternToYaml(pattern);
  if (!f) throw std::runtime_error(out + ": cannot write");
  std::cout << vt::json::Obj()
                   .add("panels", pattern.panels.size())
                   .add("seams", pattern.seams.size())
                   .add("openings", vt::patternOpenings(pattern))
                   .json("stitches", stitchesJson(rep))
                   .str()
            << std::endl;
  return 0;
}

// The drape's parameters from its options (tryon drape, tryon animate drape).
vt::DrapeParams drapeParams(const std::map<std::string, std::string>& opt) {
  vt::DrapeParams p;
  p.spacing = number(opt, "spacing", p.spacing);
  if (opt.count("mode")) {
    const std::string& m = opt.at("mode");
    if (m == "image")
      p.mode = vt::CollisionMode::ImageSpace;
    else if (m == "object")
      p.mode = vt::CollisionMode::ObjectSpace;
    else
      throw Usage("--mode must be 'image' or 'object', got '" + m + "'");
  }
  p.dt = number(opt, "dt", p.dt);
  p.max_iterations = integer(opt, "max-iterations", p.max_iterations, 1, 1000000000);
  p.resolve = !opt.count("no-resolve");
  p.collision.tol = number(opt, "tol", p.collision.tol);
  p.collision.friction = number(opt, "friction", p.collision.friction);
  p.collision.map_size = integer(opt, "map-size", p.collision.map_size, 0, 1000000000);
  p.cloth.density = number(opt, "density", p.cloth.density);
  p.cloth.k_structural = number(opt, "k-structural", p.cloth.k_structural);
  p.cloth.k_shear = number(opt, "k-shear", p.cloth.k_shear);
  p.cloth.k_flexion = number(opt, "k-flexion", p.cloth.k_flexion);
  p.max_strain = number(opt, "max-strain", p.max_strain);
  p.resolver.body_uncertainty = number(opt, "body-uncertainty", 0.0);
  if (p.resolver.body_uncertainty < 0) throw Usage("--body-uncertainty must be >= 0 (metres)");
  p.limits = meshLimits(opt);
  const std::string bad = vt::validateDrapeParams(p);
  if (!bad.empty()) throw std::invalid_argument(bad);
  return p;
}

// Progress of a drape on stderr, at most every 2 s.
vt::DrapeProgressCallback drapeProgress() {
  auto last = std::make_shared<std::chrono::steady_clock::time_point>(std::chrono::steady_clock::now());
  return [last](const vt::DrapeProgress& pr) {
    const auto now = std::chrono::steady_clock::now();
    if (now - *last >= std::chrono::seconds(2)) {
      *last = now;
      std::cerr << "tryon: drape: iteration " << pr.iteration << (pr.sewing ? " (sewing)" : " (draping)")
                << ", " << pr.seconds << " s, max speed " << pr.max_speed << " m/s\n";
    }
    return true;
  };
}

int drape(const std::map<std::string, std::string>& opt) {
  const std::string bodyPath = required(opt, "body");
  const std::string patternPath = required(opt, "pattern");
  const std::string out = required(opt, "out");
  const vt::DrapeParams p = drapeParams(opt);

  const vt::Body body(loadBody(bodyPath, p.limits).mesh);
  const vt::Pattern pattern = loadPattern(patternPath, p.spacing, &body, opt);
  vt::TriMesh garment;
  const vt::DrapeResult rep = vt::drape(body, pattern, p, garment, drapeProgress());
  std::cout << vt::toJson(rep) << std::endl;
  if (!rep.success) {
    std::cerr << "tryon: drape failed: " << rep.message << "\n";
    return 2;
  }
  for (const std::string& w : rep.warnings) std::cerr << "warning: " << w << "\n";
  save(out, garment);
  if (opt.count("render")) renderPictures(body.mesh(), garment, rep.vertex_strain, opt.at("render"), opt, stem(patternPath));
  return rep.converged ? 0 : 3;
}

// frames, ms_mean, ms_median and ms_max of per-frame milliseconds.
void addFrameTimes(vt::json::Obj& summary, const std::vector<double>& ms) {
  std::vector<double> sorted = ms;
  std::sort(sorted.begin(), sorted.end());
  double mean = 0;
  for (double m : ms) mean += m;
  mean = ms.empty() ? 0 : mean / ms.size();
  summary.add("frames", ms.size())
      .add("ms_mean", mean)
      .add("ms_median", sorted.empty() ? 0.0 : sorted[sorted.size() / 2])
      .add("ms_max", sorted.empty() ? 0.0 : sorted.back());
}

// A body cache for the rest body (its vertex count); throws with the option's name.
vt::PointCache loadBodyCache(const std::map<std::string, std::string>& opt, const vt::BodyPreparation& rest) {
  vt::PointCache cache;
  std::string err;
  if (!vt::readPointCache(required(opt, "body-cache"), cache, err, static_cast<int>(rest.mesh.V.rows())))
    throw std::invalid_argument("--body-cache " + err);
  if (cache.samples.empty()) throw std::invalid_argument("--body-cache " + opt.at("body-cache") + ": no frames");
  return cache;
}

// The largest edge strain of V against the input (same faces).
double largestStrain(const vt::MatrixX3d& input, const vt::MatrixX3i& F, const vt::MatrixX3d& V) {
  double largest = 0;
  for (double v : vt::vertexEdgeStrain(vt::TriMesh{input, F}, V)) largest = std::max(largest, v);
  return largest;
}

// The referee's counts of a frame in its JSON line; dirty when it found a crossing or a vertex inside.
void refereeLine(vt::json::Obj& line, const vt::Body& body, const vt::TriMesh& garment, char& dirty) {
  const vt::ReferenceCounts c = vt::referenceCounts(body.mesh(), garment, body.closed());
  dirty = c.garment_edge_crossings + c.body_edge_crossings + c.vertices_inside > 0;
  line.json("referee", vt::toJson(c));
}

// tryon animate resolve's second pass (limitCorrectionChangeBackward): each frame it moves is
// refitted again from `body` (the last frame's, then each moved one's), said in a
// {"backward_frame": k, ...} line, checked again by the referee with --check.
vt::BackwardCoherenceReport backwardPass(vt::PointCache& result, const vt::PointCache& inputs, const vt::MatrixX3i& F,
                                         const vt::PointCache& bodyCache, std::unique_ptr<vt::Body>& body,
                                         const std::vector<double>& minClearance, const vt::CoherenceParams& params,
                                         bool check, std::vector<char>& dirty) {
  auto bodyAt = [&](int k) -> const vt::Body& {
    body = std::make_unique<vt::Body>(std::move(*body), bodyCache.samples[static_cast<std::size_t>(k)]);
    return *body;
  };
  const vt::BackwardCoherenceReport rep =
      vt::limitCorrectionChangeBackward(result.samples, inputs.samples, F, bodyAt, minClearance, params);
  if (!rep.message.empty()) throw std::runtime_error("the backward pass: " + rep.message);
  for (std::size_t i = 0; i < rep.frames.size(); ++i) {
    const std::size_t k = static_cast<std::size_t>(rep.frames[i]);
    const vt::CoherenceReport& c = rep.reports[i];
    vt::json::Obj line;
    line.add("backward_frame", k)
        .add("over_max_jitter", c.candidates)
        .add("limited", c.limited)
        .add("partly", c.partly)
        .add("held", c.held)
        .add("jitter_to_next_as_resolved_m", c.change_before)
        .add("jitter_to_next_m", c.change_after)
        .add("strain_vs_input_max", largestStrain(inputs.samples[k], F, result.samples[k]))
        .add("ms", 1e3 * c.seconds);
    if (check) {
      // The frames are moved last first: frame k's body is refitted once more for its check.
      const vt::Body frameBody(*body, bodyCache.samples[k]);
      refereeLine(line, frameBody, vt::TriMesh{result.samples[k], F}, dirty[k]);
    }
    std::cout << line.str() << std::endl;
  }
  return rep;
}

// tryon animate resolve: every frame of a garment cache resolved on the body cache's frame.
int animateResolve(const std::map<std::string, std::string>& opt) {
  const vt::MeshLimits limits = meshLimits(opt);
  const vt::BodyPreparation rest = loadBody(required(opt, "body"), limits);
  const vt::TriMesh garmentRest = loadGarment(required(opt, "garment"), limits);
  const std::string out = required(opt, "out");
  const vt::PointCache bodyCache = loadBodyCache(opt, rest);
  vt::PointCache garmentCache;
  std::string err;
  if (!vt::readPointCache(required(opt, "garment-cache"), garmentCache, err, static_cast<int>(garmentRest.V.rows())))
    throw std::invalid_argument("--garment-cache " + err);
  if (bodyCache.samples.size() != garmentCache.samples.size())
    throw std::invalid_argument("the body cache has " + std::to_string(bodyCache.samples.size()) +
                                " frames, the garment cache " + std::to_string(garmentCache.samples.size()));
  vt::ResolverParams params = resolverParams(opt);
  params.warm_local_relaxation = opt.count("full-relaxation") == 0;
  params.warm_full_relaxation_strain = number(opt, "widen-strain", params.warm_full_relaxation_strain);
  if (!(params.warm_full_relaxation_strain >= 0 && params.warm_full_relaxation_strain <= 10))
    throw Usage("--widen-strain must be in [0, 10]");
  const bool check = opt.count("check") > 0;
  const bool warm = opt.count("cold") == 0;
  const double warmMin = number(opt, "warm-min", vt::defaultWarmStartMin(params));
  if (!(warmMin >= 0 && warmMin <= 1)) throw Usage("--warm-min must be in [0, 1] m");
  std::size_t coldFallbacks = 0, widened = 0;
  // The garment's edge lists and neighbour graph, built once for every frame's calls.
  params.connectivity = vt::garmentConnectivity(garmentRest);
  vt::CoherenceParams coherenceParams;
  coherenceParams.connectivity = params.connectivity;
  coherenceParams.max_change = number(opt, "max-jitter", coherenceParams.max_change);
  if (!(coherenceParams.max_change >= 0 && coherenceParams.max_change <= 1))
    throw Usage("--max-jitter must be in [0, 1] m (0: off)");
  std::size_t coherenceCandidates = 0, coherenceHeld = 0, coherenceForced = 0;
  double jitterMaxUnforced = 0;
  vt::PointCache result = garmentCache;
  std::vector<double> ms;
  double jitterMax = 0;
  std::size_t notConverged = 0, refereeDirty = 0;
  vt::MatrixX3d previousCorrection;
  std::unique_ptr<vt::Body> last;
  std::vector<double> minClearance;  // per frame: what the coherence steps keep off the body
  std::vector<char> dirty;           // per frame: the referee found something (--check)
  std::size_t refitted = 0;
  for (std::size_t f = 0; f < bodyCache.samples.size(); ++f) {
    const auto t0 = std::chrono::steady_clock::now();
    // Frame 0 builds the body (topology, adjacency, trees); every later frame reuses them and
    // refits the trees to its vertices.
    auto next = last ? std::make_unique<vt::Body>(std::move(*last), bodyCache.samples[f])
                     : std::make_unique<vt::Body>(vt::TriMesh{bodyCache.samples[f], rest.mesh.F});
    if (next->bvhRefitted()) ++refitted;
    last = std::move(next);
    const vt::Body& body = *last;
    const double bodyMs = 1e3 * std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    vt::TriMesh garment{garmentCache.samples[f], garmentRest.F};
    // Warm start (the default; --cold turns it off): the frame starts from its input moved by the
    // previous frame's correction, and the resolver checks and fixes it as a whole (each frame is
    // correct on its own) and relaxes it against this frame's input. Where a warm frame does not
    // converge, the frame is resolved again from its input alone.
    vt::FrameStart start = vt::FrameStart::Cold;
    vt::PreviousFrame previous;
    if (warm && f > 0) previous = vt::PreviousFrame{garmentCache.samples[f - 1], previousCorrection};
    const vt::ResolverReport rep = vt::resolveFrame(body, garment, previous, params, warmMin, &start);
    const bool warmNow = start == vt::FrameStart::Warm;
    if (start == vt::FrameStart::WarmFailedResolvedCold) ++coldFallbacks;
    if (rep.relaxation_widened) ++widened;
    // Where the correction jumped since the frame before, the clean position nearest to the
    // previous correction (core/resolve/temporal_coherence.h).
    vt::CoherenceReport coherence;
    const bool coherent = coherenceParams.max_change > 0 && rep.converged && previousCorrection.rows() == garment.V.rows();
    if (coherent) {
      vt::CoherenceParams cp = coherenceParams;
      cp.min_clearance = 0.5 * rep.clearance;
      minClearance.push_back(cp.min_clearance);
      coherence = vt::limitCorrectionChange(body, garment, garmentCache.samples[f], previousCorrection, cp);
      coherenceCandidates += coherence.candidates;
      coherenceHeld += coherence.held + coherence.partly;
      coherenceForced += coherence.forced_by_input;
    }
    if (!coherent) minClearance.push_back(0.5 * rep.clearance);
    const double frameMs = 1e3 * std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    ms.push_back(frameMs);
    const vt::MatrixX3d correction = garment.V - garmentCache.samples[f];
    // Edge strain against this frame's own input, after the coherence step (the resolver's report
    // measures before it).
    const double strainVsInput = largestStrain(garmentCache.samples[f], garmentRest.F, garment.V);
    const double jitter = previousCorrection.rows() == correction.rows()
                              ? (correction - previousCorrection).rowwise().norm().maxCoeff()
                              : 0.0;
    if (f > 0) {
      jitterMax = std::max(jitterMax, jitter);
      jitterMaxUnforced = std::max(jitterMaxUnforced, coherent ? coherence.change_after_unforced : jitter);
    }
    previousCorrection = correction;
    result.samples[f] = garment.V;
    if (!rep.converged) ++notConverged;
    vt::json::Obj line;
    line.add("frame", f)
        .add("converged", rep.converged)
        .add("crossings_before", rep.garment_edge_crossings_before + rep.body_edge_crossings_before)
        .add("crossings_after", rep.garment_edge_crossings_after + rep.body_edge_crossings_after)
        .add("inside_before", rep.vertices_inside_before)
        .add("inside_after", rep.vertices_inside_after)
        .add("iterations", rep.iterations)
        .add("max_displacement_m", rep.max_displacement)
        .add("max_edge_strain", rep.max_edge_strain)
        .add("p99_edge_strain", rep.p99_edge_strain)
        .add("strain_vs_input_max", strainVsInput)
        .add("max_correction_m", correction.rowwise().norm().maxCoeff())
        .add("jitter_m", jitter)
        .add("ms", frameMs)
        .add("ms_body", bodyMs)
        .add("ms_body_tree", 1e3 * body.bvhBuildSeconds())
        .add("ms_resolve", 1e3 * rep.seconds_total)
        .add("ms_detection", 1e3 * rep.seconds_detection)
        .add("ms_solve", 1e3 * rep.seconds_solve)
        .add("ms_relaxation", 1e3 * rep.seconds_relaxation)
        .add("ms_relaxation_setup", 1e3 * rep.relaxation.seconds_setup)
        .add("ms_relaxation_rotations", 1e3 * rep.relaxation.seconds_rotations)
        .add("ms_relaxation_checks", 1e3 * rep.relaxation.seconds_checks)
        .add("relaxed_vertices", rep.relaxation.active_vertices)
        .add("relaxation_sweeps", rep.relaxation.sweeps)
        .add("relaxation_local", rep.relaxation.local)
        .add("relaxation_widened", rep.relaxation_widened)
        .add("warm_start", warmNow);
    if (coherent)
      line.json("coherence", vt::json::Obj()
                                 .add("over_max_jitter", coherence.candidates)
                                 .add("limited", coherence.limited)
                                 .add("partly", coherence.partly)
                                 .add("held", coherence.held)
                                 .add("forced_by_input", coherence.forced_by_input)
                                 .add("refused_for_strain", coherence.strain_refusals)
                                 .add("jitter_as_resolved_m", coherence.change_before)
                                 .add("ms", 1e3 * coherence.seconds)
                                 .str());
    dirty.push_back(0);
    if (check) refereeLine(line, body, garment, dirty.back());
    std::cout << line.str() << std::endl;
  }
  const bool backwardRan = coherenceParams.max_change > 0 && !opt.count("no-backward");
  const vt::BackwardCoherenceReport backward =
      backwardRan
          ? backwardPass(result, garmentCache, garmentRest.F, bodyCache, last, minClearance, coherenceParams, check, dirty)
          : vt::BackwardCoherenceReport();
  for (char d : dirty) refereeDirty += d ? 1 : 0;
  if (!vt::writePointCache(out, result, err)) throw std::runtime_error(err);
  vt::json::Obj summary;
  addFrameTimes(summary, ms);
  summary.add("not_converged", notConverged)
      .add("jitter_max_m", backwardRan ? backward.change_after : jitterMax)
      .add("jitter_max_forward_m", jitterMax)
      .add("max_jitter_m", coherenceParams.max_change)
      .add("backward_pass", backwardRan)
      .add("backward_frames_moved", backward.frames.size())
      .add("backward_vertices_over_max_jitter", backward.candidates)
      .add("backward_vertices_left_over", backward.partly + backward.held)
      .add("ms_backward", 1e3 * backward.seconds)
      .add("ms_mean_with_backward", ms.empty() ? 0.0 : (std::accumulate(ms.begin(), ms.end(), 0.0) + 1e3 * backward.seconds) / ms.size())
      .add("warm_start", warm)
      .add("warm_min_m", warmMin)
      .add("warm_frames_resolved_cold", coldFallbacks)
      .add("warm_local_relaxation", warm && params.warm_local_relaxation)
      .add("relaxations_widened", widened)
      .add("vertices_over_max_jitter", coherenceCandidates)
      .add("vertices_left_over_max_jitter", coherenceHeld)
      .add("vertices_left_over_forced_by_input", coherenceForced)
      .add("jitter_max_unforced_m", jitterMaxUnforced)
      .add("body_trees_refitted", refitted)
      .add("body_trees_built", ms.size() - refitted)
      .add("rebuilt_per_frame", std::string("body bounds and volume (face, edge and vertex normals when asked for)"))
      .add("reused", std::string("body topology, edge and vertex-face lists; the face tree refitted"));
  if (check) summary.add("frames_with_referee_findings", refereeDirty);
  std::cout << vt::json::Obj().json("summary", summary.str()).str() << std::endl;
  return notConverged == 0 && refereeDirty == 0 ? 0 : 3;
}

// OUT.obj and OUT.pc2 from --out (either name, or a name without those extensions).
std::pair<std::string, std::string> objAndCache(const std::string& out) {
  for (const char* ext : {".pc2", ".obj"})
    if (out.size() > 4 && out.compare(out.size() - 4, 4, ext) == 0) {
      const std::string base = out.substr(0, out.size() - 4);
      return {base + ".obj", base + ".pc2"};
    }
  return {out + ".obj", out + ".pc2"};
}

// One frame of tryon animate drape as a JSON line.
vt::json::Obj wornFrameJson(std::size_t frame, const vt::WornFrameReport& r, double msBody, double ms) {
  vt::json::Obj line;
  line.add("frame", frame)
      .add("success", r.success)
      .add("converged", r.converged)
      .add("steps", r.steps)
      .add("dt_s", r.dt)
      .add("step_halvings", r.step_halvings)
      .add("interpolated", r.interpolated)
      .add("grid_rebuilt", r.grid_rebuilt)
      .add("colliding_nodes", r.colliding_nodes)
      .add("strain_max", r.strain_max)
      .add("strain_stepped", r.strain_stepped)
      .add("relax_passes", r.relax_passes)
      .add("resolved_relaxed", r.resolved_relaxed)
      .add("carried_with_skin", r.carried)
      .add("quick_correction", r.quick_correction)
      .add("carried_for_strain", r.carried_for_strain)
      .add("max_speed_m_s", r.max_speed);
  if (r.resolver_run)
    line.add("crossings_before", r.resolver.garment_edge_crossings_before + r.resolver.body_edge_crossings_before)
        .add("crossings_after", r.resolver.garment_edge_crossings_after + r.resolver.body_edge_crossings_after)
        .add("inside_before", r.resolver.vertices_inside_before)
        .add("inside_after", r.resolver.vertices_inside_after)
        .add("resolver_iterations", r.resolver.iterations)
        .add("resolver_max_displacement_m", r.resolver.max_displacement)
        .add("ms_resolve_detection", 1e3 * r.resolver.seconds_detection)
        .add("ms_resolve_solve", 1e3 * r.resolver.seconds_solve)
        .add("ms_resolve_relaxation", 1e3 * r.resolver.seconds_relaxation)
        .add("ms_relaxation_setup", 1e3 * r.resolver.relaxation.seconds_setup)
        .add("ms_relaxation_rotations", 1e3 * r.resolver.relaxation.seconds_rotations)
        .add("ms_relaxation_checks", 1e3 * r.resolver.relaxation.seconds_checks)
        .add("relaxed_vertices", r.resolver.relaxation.active_vertices);
  line.add("ms", ms)
      .add("ms_body", msBody)
      .add("ms_maps", 1e3 * r.seconds_maps)
      .add("ms_cloth", 1e3 * r.seconds_cloth)
      .add("ms_resolve", 1e3 * r.seconds_resolve)
      .add("message", r.message);
  return line;
}

// tryon animate drape: the pattern draped on the body cache's first frame, then worn through the
// motion (core/drape/worn_garment.h).
int animateDrape(const std::map<std::string, std::string>& opt) {
  const vt::MeshLimits limits = meshLimits(opt);
  const vt::BodyPreparation rest = loadBody(required(opt, "body"), limits);
  const vt::PointCache bodyCache = loadBodyCache(opt, rest);
  const auto outs = objAndCache(required(opt, "out"));
  const std::string patternPath = required(opt, "pattern");
  const double fps = number(opt, "fps", 30.0);
  if (!(fps > 0 && fps <= 10000)) throw Usage("--fps must be in (0, 10000] frames per second");
  const int count = static_cast<int>(bodyCache.samples.size());
  const int frames = integer(opt, "frames", count, 1, count);
  vt::WornGarmentParams wp;
  wp.drape = drapeParams(opt);
  wp.dt = number(opt, "cloth-dt", 0.0);
  wp.body_velocity = !opt.count("no-body-velocity");
  wp.top_view = !opt.count("no-top-view");
  wp.skin_velocity = !opt.count("no-skin-velocity");
  wp.resolve_relaxed = !opt.count("no-resolve-relaxed");
  wp.carry_with_skin = !opt.count("no-carry");
  wp.side_view = opt.count("side-view") > 0;
  wp.interpolate = !opt.count("no-interpolate");
  wp.strain_restore = number(opt, "strain-restore", wp.strain_restore);
  wp.relax_compression = number(opt, "relax-compression", wp.relax_compression);
  wp.quick_sweeps = integer(opt, "quick-sweeps", wp.quick_sweeps, 0, 1000);
  const bool check = opt.count("check") > 0;
  const int framesAhead = integer(opt, "frames-ahead", vt::FramesAhead::kDefaultDepth, 1, 64);

  auto body = std::make_unique<vt::Body>(vt::TriMesh{bodyCache.samples[0], rest.mesh.F});
  const vt::Pattern pattern = loadPattern(patternPath, wp.drape.spacing, body.get(), opt);
  vt::WornGarment worn(wp);
  // The next frames' bodies and maps are made ready on a second thread while the cloth steps
  // through frame f, at most --frames-ahead of them waiting (--sequential: one after the other),
  // the first ones while frame 0 is draped. A frame's ms
  // is the wall time from the end of the frame before (frame 1: of the drape) to its end (the
  // referee's count of --check left out): with frames made ahead, what each costs in a run of them.
  const std::vector<vt::MatrixX3d> bodyFrames(bodyCache.samples.begin(), bodyCache.samples.begin() + frames);
  std::unique_ptr<vt::FramesAhead> ahead;
  const vt::Body& first = *body;  // FramesAhead keeps it, and only reads it until its first frame
  const auto t0 = std::chrono::steady_clock::now();
  const vt::DrapeResult dressed =
      worn.dress(first, pattern, drapeProgress(), 25, [&](const vt::WornMapRenderer& renderer) {
        ahead = std::make_unique<vt::FramesAhead>(std::move(body), bodyFrames, renderer, 1.0 / fps,
                                                  !opt.count("sequential"), framesAhead);
      });
  const double dressMs = 1e3 * std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  std::cout << vt::json::Obj()
                   .add("frame", 0)
                   .json("drape", vt::toJson(dressed))
                   .add("ms", dressMs)
                   .add("cloth_dt_s", worn.clothStep())
                   .add("cloth_dt_limit_s", worn.stepLimit())
                   .str()
            << std::endl;
  if (!dressed.success) {
    std::cerr << "tryon: drape failed: " << dressed.message << "\n";
    return 2;
  }
  vt::PointCache result;
  result.points = static_cast<int>(worn.garment().V.rows());
  result.start_frame = bodyCache.start_frame;
  result.sample_rate = bodyCache.sample_rate;
  result.samples.push_back(worn.garment().V);
  save(outs.first, worn.garment());
  std::size_t notConverged = dressed.converged ? 0 : 1, refereeDirty = 0, gridRebuilt = 0, carried = 0, quick = 0;
  double strainMax = 0;
  std::vector<double> ms;
  std::string failure;
  auto tf = std::chrono::steady_clock::now();
  while (!ahead->done() && failure.empty()) {
    vt::FramesAhead::Frame next = ahead->next();
    const int f = next.index;
    const vt::Body* frameBody = next.body;
    const double msRender = 1e3 * next.maps.seconds_render;
    const vt::WornFrameReport r = worn.follow(*frameBody, std::move(next.maps));
    const auto now = std::chrono::steady_clock::now();
    const double frameMs = 1e3 * std::chrono::duration<double>(now - tf).count();
    tf = now;
    vt::json::Obj line = wornFrameJson(static_cast<std::size_t>(f), r, 1e3 * next.seconds_body, frameMs);
    line.add("ms_waited", 1e3 * next.seconds_waited)
        .add("ms_ahead", 1e3 * next.seconds_body + msRender)
        .add("frames_ready_after", next.queued);
    if (!r.success) {
      failure = "frame " + std::to_string(f) + ": " + r.message;
    } else {
      ms.push_back(frameMs);
      result.samples.push_back(worn.garment().V);
      strainMax = std::max(strainMax, r.strain_max);
      if (!r.converged) ++notConverged;
      if (r.grid_rebuilt) ++gridRebuilt;
      if (r.carried) ++carried;
      if (r.quick_correction) ++quick;
      if (check) {  // not counted in the next frame's ms
        const auto tc = std::chrono::steady_clock::now();
        const vt::ReferenceCounts c = vt::referenceCounts(frameBody->mesh(), worn.garment(), frameBody->closed());
        if (c.garment_edge_crossings + c.body_edge_crossings + c.vertices_inside) ++refereeDirty;
        line.json("referee", vt::toJson(c));
        tf += std::chrono::steady_clock::now() - tc;
      }
    }
    std::cout << line.str() << std::endl;
  }
  std::string err;
  if (!vt::writePointCache(outs.second, result, err)) throw std::runtime_error(err);
  std::cerr << "tryon: wrote " << outs.first << " and " << outs.second << " (" << result.samples.size() << " frames)\n";
  vt::json::Obj summary;
  addFrameTimes(summary, ms);
  summary.add("frames_written", result.samples.size())
      .add("not_converged", notConverged)
      .add("strain_max", strainMax)
      .add("grids_rebuilt", gridRebuilt)
      .add("frames_carried_with_skin", carried)
      .add("frames_corrected_quickly", quick)
      .add("drape_ms", dressMs)
      .add("failure", failure);
  if (check) summary.add("frames_with_referee_findings", refereeDirty);
  std::cout << vt::json::Obj().json("summary", summary.str()).str() << std::endl;
  if (!failure.empty()) std::cerr << "tryon: " << failure << "\n";
  return failure.empty() && notConverged == 0 && refereeDirty == 0 ? 0 : 3;
}

int render(const std::map<std::string, std::string>& opt) {
  const vt::MeshLimits limits = meshLimits(opt);
  const vt::BodyPreparation body = loadBody(required(opt, "body"), limits);
  const std::string garmentPath = required(opt, "garment");
  const vt::TriMesh garment = loadGarment(garmentPath, limits);
  std::vector<double> strain;
  if (opt.count("reference")) {
    const vt::TriMesh input = loadGarment(opt.at("reference"), limits);
    if (input.V.rows() != garment.V.rows() || input.F != garment.F)
      throw std::invalid_argument("--reference " + opt.at("reference") +
                                  ": not the garment's faces and vertex order");
    strain = vt::vertexEdgeStrain(input, garment.V);
  }
  renderPictures(body.mesh, garment, strain, required(opt, "out"), opt, stem(garmentPath));
  return 0;
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

// VTK on Debian renders through X: without a display, run this same command under xvfb-run (a
// virtual X server). Returns only when xvfb-run cannot be started (the render then says why).
void reexecUnderXvfb(int argc, char** argv) {
  if (std::getenv("VIRTUAL_TRYON_IN_XVFB")) return;  // never twice
  ::setenv("VIRTUAL_TRYON_IN_XVFB", "1", 1);
  std::vector<char*> args{const_cast<char*>("xvfb-run"), const_cast<char*>("-a"), const_cast<char*>("-s"),
                          const_cast<char*>("-screen 0 1280x1024x24")};
  for (int i = 0; i < argc; ++i) args.push_back(argv[i]);
  args.push_back(nullptr);
  ::execvp("xvfb-run", args.data());
  warn("no X display and xvfb-run could not be started (install xvfb: scripts/setup.sh)");
}

}  // namespace

int main(int argc, char** argv) {
  virtual_tryon::keepHeapForFrames();
  try {
    if (argc < 2 || std::string(argv[1]) == "--help" || std::string(argv[1]) == "-h") {
      std::cout << usage();
      return argc < 2 ? 2 : 0;
    }
    const std::string cmd = argv[1];
    const auto opt = parseOptions(argc, argv, cmd == "animate" ? std::min(argc, 3) : 2);
    if ((cmd == "render" || opt.count("render")) && !std::getenv("DISPLAY")) reexecUnderXvfb(argc, argv);
    if (cmd == "resolve") {
      allowOnly(opt, cmd, {"body", "garment", "out", "clearance", "body-uncertainty", "max-iterations",
                           "objective", "max-vertices", "max-faces"});
      return resolve(opt);
    }
    if (cmd == "check") {
      allowOnly(opt, cmd, {"body", "garment", "reference", "max-vertices", "max-faces"});
      return check(opt);
    }
    if (cmd == "drape") {
      allowOnly(opt, cmd, {"body", "pattern", "out", "spacing", "mode", "dt", "max-iterations",
                           "no-resolve", "tol", "friction", "map-size", "density", "k-structural", "k-shear",
                           "k-flexion", "max-strain", "body-uncertainty", "render", "strain-scale", "title",
                           "placement", "scale-to-height", "max-vertices", "max-faces"});
      return drape(opt);
    }
    if (cmd == "convert-pattern") {
      allowOnly(opt, cmd, {"in", "out", "spacing", "body", "placement", "scale-to-height", "max-vertices", "max-faces"});
      return convertPattern(opt);
    }
    if (cmd == "render") {
      allowOnly(opt, cmd, {"body", "garment", "out", "reference", "strain-scale", "title", "max-vertices", "max-faces"});
      return render(opt);
    }
    if (cmd == "animate") {
      const std::string mode = argc < 3 ? "" : argv[2];
      if (mode == "drape") {
        allowOnly(opt, "animate drape", {"body", "body-cache", "pattern", "out", "check", "fps", "frames", "cloth-dt",
                                          "no-body-velocity", "no-interpolate", "no-skin-velocity", "no-top-view", "side-view", "no-resolve-relaxed", "no-carry", "sequential", "frames-ahead", "quick-sweeps", "relax-compression", "strain-restore", "spacing", "dt", "max-iterations",
                                          "no-resolve", "tol", "friction", "map-size", "density", "k-structural", "k-shear",
                                          "k-flexion", "max-strain", "body-uncertainty", "placement", "scale-to-height",
                                          "max-vertices", "max-faces"});
        return animateDrape(opt);
      }
      if (mode != "resolve") throw Usage("'animate' needs a mode: resolve or drape");
      allowOnly(opt, "animate resolve", {"body", "body-cache", "garment", "garment-cache", "out", "check", "warm-start", "cold", "no-backward", "warm-min", "full-relaxation", "widen-strain", "max-jitter", "clearance",
                                          "body-uncertainty", "max-iterations", "objective", "max-vertices", "max-faces"});
      return animateResolve(opt);
    }
    if (cmd == "demo") {
      allowOnly(opt, cmd, {"out"});
      return demo(opt);
    }
    throw Usage("unknown command '" + cmd + "'");
  } catch (const Usage& e) {
    std::cerr << "tryon: " << e.what() << "\n" << usage();
    return 2;
  } catch (const std::exception& e) {
    std::cerr << "tryon: " << e.what() << "\n";
    return 2;
  }
}
