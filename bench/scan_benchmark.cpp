// Scan meshing benchmark: a synthetic scan (no normals, Gaussian noise) of the procedural body, or of
// a body read from a mesh file (the truth), meshed into a closed outward body; median of RUNS runs
// per stage. With --garment, the garment is then fitted to the scan's mesh (resolver, clearance d +
// the scan's 95% error) and counted against the TRUE body by the independent referee, next to a fit
// that ignores the scan's error (clearance d only).
// Usage: scan_benchmark [MESH] [--garment G] [--points N] [--noise M] [--voxel M] [--depth D]
//                       [--spn S] [--k K] [--threads T] [--runs R] [--out OBJ] [--grid]
//   defaults: the procedural body, 200000 points, noise 0.001 m, voxel 0.005 m, depth 0 (chosen),
//   3 runs. --grid: one table row for each of 50k / 100k / 200k points at 1 mm and 3 mm noise.
#include "virtual_tryon/core/body/body.h"
#include "virtual_tryon/core/body/body_check.h"
#include "virtual_tryon/core/body/scan_meshing.h"
#include "virtual_tryon/core/geometry/point_queries.h"
#include "virtual_tryon/core/io/mesh_io.h"
#include "virtual_tryon/core/resolve/penetration_resolver.h"
#include "virtual_tryon/core/scenes/procedural_body.h"
#include "virtual_tryon/core/scenes/synthetic_scan.h"
#include "virtual_tryon/testing/reference_check.h"

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <ctime>
#include <string>
#include <vector>

namespace vt = virtual_tryon;

namespace {

struct Options {
  std::string mesh, garment, out;
  vt::SyntheticScanParams scan;
  vt::ScanMeshingParams meshing;
  int runs = 3;
  bool grid = false;
};

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v.empty() ? 0.0 : v[v.size() / 2];
}

Options parse(int argc, char** argv) {
  Options o;
  o.scan.points = 200000;
  o.scan.noise_sigma = 0.001;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    auto value = [&]() -> const char* {
      if (i + 1 >= argc) {
        std::fprintf(stderr, "scan_benchmark: %s needs a value\n", a.c_str());
        std::exit(2);
      }
      return argv[++i];
    };
    if (a == "--points") o.scan.points = std::strtoul(value(), nullptr, 10);
    else if (a == "--noise") o.scan.noise_sigma = std::atof(value());
    else if (a == "--voxel") o.meshing.voxel_size = std::atof(value());
    else if (a == "--depth") o.meshing.depth = std::atoi(value());
    else if (a == "--spn") o.meshing.samples_per_node = std::atof(value());
    else if (a == "--k") o.meshing.normal_neighbours = std::atoi(value());
    else if (a == "--threads") o.meshing.threads = std::atoi(value());
    else if (a == "--runs") o.runs = std::max(1, std::atoi(value()));
    else if (a == "--out") o.out = value();
    else if (a == "--garment") o.garment = value();
    else if (a == "--grid") o.grid = true;
    else if (!a.empty() && a[0] == '-') {
      std::fprintf(stderr, "scan_benchmark: unknown option %s\n", a.c_str());
      std::exit(2);
    } else o.mesh = a;
  }
  return o;
}

bool load(const std::string& path, vt::TriMesh& m) {
  std::string err;
  if (vt::readMesh(path, m, err)) return true;
  std::fprintf(stderr, "scan_benchmark: %s\n", err.c_str());
  return false;
}

// The garment fitted to `scanMesh` with the given body uncertainty, counted against `truth`.
struct Fit {
  vt::ResolverReport report;
  vt::ReferenceCounts truth;
};
Fit fit(const vt::Body& scanMesh, const vt::TriMesh& truth, const vt::TriMesh& garment, double uncertainty) {
  Fit f;
  vt::TriMesh g = garment;
  vt::ResolverParams p;
  p.body_uncertainty = uncertainty;
  f.report = vt::resolvePenetrations(scanMesh, g, p);
  f.truth = vt::referenceCounts(truth, g);
  return f;
}

std::string counts(const vt::ReferenceCounts& c) {
  return std::to_string(c.garment_edge_crossings) + " / " + std::to_string(c.body_edge_crossings) + " / " +
         std::to_string(c.vertices_inside);
}

// Meshes `scan` runs times; prints the stage table when `verbose`. Returns the last result and the
// median total seconds in `seconds`.
vt::ScanMeshingResult meshRuns(const vt::SyntheticScan& scan, const Options& o, bool verbose, double& seconds) {
  std::vector<double> noise, down, normals, orient, recon, cleanup, error, total, cpu;
  vt::ScanMeshingResult r;
  for (int run = 0; run < o.runs; ++run) {
    const std::clock_t c0 = std::clock();
    r = vt::meshScan(scan.points, vt::MatrixX3d(), o.meshing);
    cpu.push_back(static_cast<double>(std::clock() - c0) / CLOCKS_PER_SEC);
    noise.push_back(r.seconds_noise);
    down.push_back(r.seconds_downsample);
    normals.push_back(r.seconds_normals);
    orient.push_back(r.seconds_orient);
    recon.push_back(r.seconds_reconstruct);
    cleanup.push_back(r.seconds_cleanup);
    error.push_back(r.seconds_error);
    total.push_back(r.seconds_total);
  }
  seconds = median(total);
  if (!verbose) return r;
  std::printf("\n| stage | median s (min-max) |\n|---|---|\n");
  auto row = [](const char* stage, const std::vector<double>& v) {
    std::printf("| %s | %.3f (%.3f-%.3f) |\n", stage, median(v), *std::min_element(v.begin(), v.end()),
                *std::max_element(v.begin(), v.end()));
  };
  row("noise estimate", noise);
  row("finite filter + voxel grid", down);
  row("kNN + normals", normals);
  row("orientation (MST)", orient);
  row("Poisson", recon);
  row("cleanup + body check", cleanup);
  row("error measurement", error);
  row("total", total);
  row("total, process CPU time (all threads)", cpu);
  return r;
}

void printResult(const vt::ScanMeshingResult& r, double sourceVolume) {
  std::printf("success: %s (%s)\n", r.success ? "yes" : "no", r.message.c_str());
  std::printf("points in %zu, after downsampling %zu (spacing %.2f mm), kNN graph components %zu, normals flipped %zu\n",
              r.input_points, r.points_after_downsampling, 1e3 * r.point_spacing, r.graph_components,
              r.normals_flipped);
  std::printf("Poisson depth %d: %zu vertices / %zu faces; final %zu vertices / %zu faces, cavities removed %zu, "
              "dropped pieces %zu, holes filled %zu, closed %s (%zu boundary, %zu non-manifold edges), flipped %s\n",
              r.depth, r.poisson_vertices, r.poisson_faces, r.vertices, r.faces, r.cavities_removed, r.dropped_pieces,
              r.holes_filled, r.closed ? "yes" : "no", r.boundary_edges, r.non_manifold_edges, r.flipped ? "yes" : "no");
  std::printf("volume %.5f m^3 (source %.5f, %+.2f%%)\n", r.signed_volume, sourceVolume,
              100.0 * (r.signed_volume - sourceVolume) / sourceVolume);
  std::printf("noise estimated %.3f mm (%zu samples); points to mesh (%zu points): median %.2f, 95%% %.2f, max %.2f mm, "
              "%.1f%% beyond 2 mm; 95%% / (1.96 noise) = %.2f\n",
              1e3 * r.noise.sigma, r.noise.samples, r.error.points, 1e3 * r.error.median, 1e3 * r.error.p95,
              1e3 * r.error.max, 100 * r.error.share_over_2mm, r.error_ratio);
}

// Distance of the result's vertices to the true surface.
void printTruthDistance(const vt::ScanMeshingResult& r, const vt::TriMesh& source) {
  if (r.vertices == 0) return;
  vt::Body body(source);
  std::vector<double> d;
  d.reserve(r.vertices);
  for (Eigen::Index i = 0; i < r.mesh.V.rows(); ++i)
    d.push_back(vt::closestPointOnBody(body, r.mesh.V.row(i).transpose()).distance);
  std::sort(d.begin(), d.end());
  double mean = 0;
  for (double x : d) mean += x;
  mean /= static_cast<double>(d.size());
  std::printf("distance of the result's vertices to the true surface: mean %.2f mm, 95%% %.2f mm, max %.2f mm\n",
              1e3 * mean, 1e3 * d[d.size() * 95 / 100], 1e3 * d.back());
}

const char* kHeader =
    "| points | noise mm | depth | mesh s | noise est. mm | points to mesh: median / 95% / max mm | beyond 2 mm | "
    "95% / 1.96 noise | clearance used mm | vs truth g / b / in | without the scan's error: clearance, vs truth |\n"
    "|---|---|---|---|---|---|---|---|---|---|---|\n";

// One table row for a meshed scan: its figures, then (with a garment) the two fits against the
// truth. Returns whether the fit with the scan's error is clean against the truth.
bool printRow(const vt::ScanMeshingResult& r, double seconds, const vt::TriMesh& truth, const vt::TriMesh* garment,
              const Options& o) {
  if (!r.success) {
    std::printf("| %zu | %.1f | - | - | meshing failed: %s |\n", o.scan.points, 1e3 * o.scan.noise_sigma, r.message.c_str());
    return false;
  }
  std::printf("| %zu | %.1f | %d | %.2f | %.2f | %.2f / %.2f / %.1f | %.1f%% | %.2f |", o.scan.points,
              1e3 * o.scan.noise_sigma, r.depth, seconds, 1e3 * r.noise.sigma, 1e3 * r.error.median, 1e3 * r.error.p95,
              1e3 * r.error.max, 100 * r.error.share_over_2mm, r.error_ratio);
  if (!garment) {
    std::printf(" - | - | - |\n");
    return true;
  }
  const vt::Body body(r.mesh);
  const Fit ours = fit(body, truth, *garment, r.error.p95);
  const Fit plain = fit(body, truth, *garment, 0.0);
  std::printf(" %.2f | %s%s | %.2f mm: %s |\n", 1e3 * ours.report.clearance, counts(ours.truth).c_str(),
              ours.report.converged ? "" : " (not converged)", 1e3 * plain.report.clearance,
              counts(plain.truth).c_str());
  return ours.report.converged && ours.truth.garment_edge_crossings + ours.truth.body_edge_crossings +
                                          ours.truth.vertices_inside == 0;
}

bool gridRow(const vt::TriMesh& truth, const vt::TriMesh* garment, const Options& o) {
  const vt::SyntheticScan scan = vt::syntheticScan(truth, o.scan);
  if (!scan.success) return false;
  double seconds = 0;
  const vt::ScanMeshingResult r = meshRuns(scan, o, false, seconds);
  return printRow(r, seconds, truth, garment, o);
}

}  // namespace

int main(int argc, char** argv) {
  Options o = parse(argc, argv);
  vt::TriMesh source, garment;
  std::string name = "procedural body";
  if (o.mesh.empty()) source = vt::makeProceduralBody();
  else if (!load(o.mesh, source)) return 2;
  else name = o.mesh;
  if (!o.garment.empty() && !load(o.garment, garment)) return 2;
  const vt::TriMesh* g = o.garment.empty() ? nullptr : &garment;

  if (o.grid) {
    if (o.runs == 3) o.runs = 1;
    std::printf("%s: %ld vertices; garment %s; voxel %.4f m, depth %s\n\n%s", name.c_str(),
                static_cast<long>(source.V.rows()), o.garment.empty() ? "none" : o.garment.c_str(),
                o.meshing.voxel_size, o.meshing.depth > 0 ? std::to_string(o.meshing.depth).c_str() : "chosen",
                kHeader);
    bool clean = true;
    for (double noise : {0.001, 0.003})
      for (std::size_t points : {50000, 100000, 200000}) {
        o.scan.points = points;
        o.scan.noise_sigma = noise;
        clean = gridRow(source, g, o) && clean;
      }
    return clean ? 0 : 1;
  }

  const double sourceVolume = vt::signedVolume(source);
  const vt::SyntheticScan scan = vt::syntheticScan(source, o.scan);
  if (!scan.success) {
    std::fprintf(stderr, "scan_benchmark: %s\n", scan.message.c_str());
    return 2;
  }
  std::printf("%s: %ld vertices, %ld faces, volume %.5f m^3; scan of %zu points, noise %.4f m\n", name.c_str(),
              static_cast<long>(source.V.rows()), static_cast<long>(source.F.rows()), sourceVolume, o.scan.points,
              o.scan.noise_sigma);
  std::printf("source check: %s\n", vt::checkBody(source).summary.c_str());
  std::printf("parameters: voxel %.4f m, k %d, depth %d (0: chosen), samples per node %.2f, point weight %.1f; %d runs\n",
              o.meshing.voxel_size, o.meshing.normal_neighbours, o.meshing.depth, o.meshing.samples_per_node,
              o.meshing.point_weight, o.runs);
  double seconds = 0;
  const vt::ScanMeshingResult r = meshRuns(scan, o, true, seconds);
  std::printf("\n");
  printResult(r, sourceVolume);
  printTruthDistance(r, source);
  if (r.success && g) {
    std::printf("\n%s", kHeader);
    printRow(r, seconds, source, g, o);
  }
  if (!o.out.empty()) {
    std::string err;
    if (!vt::writeMesh(o.out, r.mesh, err)) std::fprintf(stderr, "scan_benchmark: %s\n", err.c_str());
  }
  return r.success ? 0 : 1;
}
