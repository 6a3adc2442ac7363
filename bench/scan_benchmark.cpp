// Scan meshing benchmark: a synthetic scan (no normals, Gaussian noise) of the procedural body, or of
// a body read from a mesh file, meshed into a closed outward body; median of RUNS runs per stage.
// Usage: scan_benchmark [MESH] [--points N] [--noise M] [--voxel M] [--depth D] [--spn S]
//                       [--k K] [--threads T] [--runs R] [--out OBJ]
//   defaults: the procedural body, 200000 points, noise 0.001 m, voxel 0.005 m, depth 8, 3 runs.
// Also prints the distance of the result's vertices to the scanned surface (mean / 95% / max), and
// the process CPU time next to the wall-clock stages (the two differ on a shared machine).
#include "virtual_tryon/core/body/body.h"
#include "virtual_tryon/core/body/body_check.h"
#include "virtual_tryon/core/io/mesh_io.h"
#include "virtual_tryon/core/geometry/point_queries.h"
#include "virtual_tryon/core/scenes/procedural_body.h"
#include "virtual_tryon/core/body/scan_meshing.h"
#include "virtual_tryon/core/scenes/synthetic_scan.h"

#include <algorithm>
#include <ctime>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

namespace vt = virtual_tryon;

namespace {

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v.empty() ? 0.0 : v[v.size() / 2];
}

}  // namespace

int main(int argc, char** argv) {
  std::string meshPath, outPath;
  vt::SyntheticScanParams scanParams;
  scanParams.points = 200000;
  scanParams.noise_sigma = 0.001;
  vt::ScanMeshingParams params;
  params.voxel_size = 0.005;
  int runs = 3;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    auto value = [&]() -> const char* {
      if (i + 1 >= argc) {
        std::fprintf(stderr, "scan_benchmark: %s needs a value\n", a.c_str());
        std::exit(2);
      }
      return argv[++i];
    };
    if (a == "--points") scanParams.points = std::strtoul(value(), nullptr, 10);
    else if (a == "--noise") scanParams.noise_sigma = std::atof(value());
    else if (a == "--voxel") params.voxel_size = std::atof(value());
    else if (a == "--depth") params.depth = std::atoi(value());
    else if (a == "--spn") params.samples_per_node = std::atof(value());
    else if (a == "--k") params.normal_neighbours = std::atoi(value());
    else if (a == "--threads") params.threads = std::atoi(value());
    else if (a == "--runs") runs = std::max(1, std::atoi(value()));
    else if (a == "--out") outPath = value();
    else if (!a.empty() && a[0] == '-') {
      std::fprintf(stderr, "scan_benchmark: unknown option %s\n", a.c_str());
      return 2;
    } else meshPath = a;
  }

  vt::TriMesh source;
  std::string name = "procedural body";
  if (meshPath.empty()) {
    source = vt::makeProceduralBody();
  } else {
    std::string err;
    if (!vt::readMesh(meshPath, source, err)) {
      std::fprintf(stderr, "scan_benchmark: %s\n", err.c_str());
      return 2;
    }
    name = meshPath;
  }
  const double sourceVolume = vt::signedVolume(source);
  const vt::BodyCheck sourceCheck = vt::checkBody(source);
  const vt::SyntheticScan scan = vt::syntheticScan(source, scanParams);
  if (!scan.success) {
    std::fprintf(stderr, "scan_benchmark: %s\n", scan.message.c_str());
    return 2;
  }
  std::printf("%s: %ld vertices, %ld faces, volume %.5f m^3; scan of %zu points, noise %.4f m\n", name.c_str(),
              static_cast<long>(source.V.rows()), static_cast<long>(source.F.rows()), sourceVolume, scanParams.points,
              scanParams.noise_sigma);
  std::printf("source check: %s\n", sourceCheck.summary.c_str());
  std::printf("parameters: voxel %.4f m, k %d, depth %d, samples per node %.2f, point weight %.1f; %d runs\n\n",
              params.voxel_size, params.normal_neighbours, params.depth, params.samples_per_node,
              params.point_weight, runs);

  std::vector<double> down, normals, orient, recon, cleanup, total, cpu;
  vt::ScanMeshingResult r;
  for (int run = 0; run < runs; ++run) {
    const std::clock_t c0 = std::clock();
    r = vt::meshScan(scan.points, vt::MatrixX3d(), params);
    cpu.push_back(static_cast<double>(std::clock() - c0) / CLOCKS_PER_SEC);
    down.push_back(r.seconds_downsample);
    normals.push_back(r.seconds_normals);
    orient.push_back(r.seconds_orient);
    recon.push_back(r.seconds_reconstruct);
    cleanup.push_back(r.seconds_cleanup);
    total.push_back(r.seconds_total);
  }
  std::printf("success: %s (%s)\n", r.success ? "yes" : "no", r.message.c_str());
  std::printf("points in %zu, after downsampling %zu, kNN graph components %zu, normals flipped %zu\n",
              r.input_points, r.points_after_downsampling, r.graph_components, r.normals_flipped);
  std::printf("Poisson %zu vertices / %zu faces; final %zu vertices / %zu faces, cavities removed %zu, dropped pieces %zu, holes filled %zu, "
              "closed %s (%zu boundary, %zu non-manifold edges), flipped %s\n",
              r.poisson_vertices, r.poisson_faces, r.vertices, r.faces, r.cavities_removed, r.dropped_pieces, r.holes_filled,
              r.closed ? "yes" : "no",
              r.boundary_edges, r.non_manifold_edges, r.flipped ? "yes" : "no");
  std::printf("volume %.5f m^3 (source %.5f, %+.2f%%)\n", r.signed_volume, sourceVolume,
              100.0 * (r.signed_volume - sourceVolume) / sourceVolume);
  std::printf("\n| stage | median s (min-max) |\n|---|---|\n");
  auto row = [](const char* stage, const std::vector<double>& v) {
    std::printf("| %s | %.3f (%.3f-%.3f) |\n", stage, median(v), *std::min_element(v.begin(), v.end()),
                *std::max_element(v.begin(), v.end()));
  };
  row("finite filter + voxel grid", down);
  row("kNN + normals", normals);
  row("orientation (MST)", orient);
  row("Poisson", recon);
  row("cleanup + body check", cleanup);
  row("total", total);
  row("total, process CPU time", cpu);

  if (r.vertices > 0) {
    vt::Body body(source);
    std::vector<double> d;
    d.reserve(r.vertices);
    Eigen::Index far = 0;
    for (Eigen::Index i = 0; i < r.mesh.V.rows(); ++i) {
      d.push_back(vt::closestPointOnBody(body, r.mesh.V.row(i).transpose()).distance);
      if (d.back() > d[static_cast<std::size_t>(far)]) far = i;
    }
    std::vector<double> sorted = d;
    std::sort(sorted.begin(), sorted.end());
    double mean = 0;
    for (double x : d) mean += x;
    mean /= static_cast<double>(d.size());
    std::size_t over5mm = 0;
    for (double x : d) over5mm += x > 0.005;
    std::printf("\ndistance of the result's vertices to the source surface: mean %.2f mm, 95%% %.2f mm, max %.2f mm "
                "at (%.3f, %.3f, %.3f); %zu vertices beyond 5 mm\n",
                1e3 * mean, 1e3 * sorted[sorted.size() * 95 / 100], 1e3 * sorted.back(), r.mesh.V(far, 0),
                r.mesh.V(far, 1), r.mesh.V(far, 2), over5mm);
  }
  if (!outPath.empty()) {
    std::string err;
    if (!vt::writeMesh(outPath, r.mesh, err)) std::fprintf(stderr, "scan_benchmark: %s\n", err.c_str());
  }
  return r.success ? 0 : 1;
}
