// Resolver benchmark on the shared MakeHuman meshes: body_hm08 with each garment, every method.
// Usage: resolve_benchmark [DATA_DIR] [RUNS]   (DATA_DIR default: ../shared/data, or $VT_DATA)
// Prints one Markdown table, a row per garment and method (ours: the smooth objective; the
// paper's formulation; per-stencil projection; the vertex push-out baseline), judged by the
// independent referee: crossings and inside vertices left, edge strain against the input (max /
// p99), largest displacement against the need (the least lift any resolver must make), vertices
// that started more than 1 cm from the body and moved more than 1 mm, and the time (median of RUNS
// calls, the body's BVH built once before). Skips (exit 0) when the data is absent; exit 1 when
// our method leaves a crossing or an inside vertex.
#include "virtual_tryon/core/body/body.h"
#include "virtual_tryon/heap_settings.h"
#include "virtual_tryon/core/io/mesh_io.h"
#include "virtual_tryon/core/resolve/penetration_resolver.h"
#include "virtual_tryon/testing/push_out_baseline.h"
#include "virtual_tryon/testing/reference_bvh.h"
#include "virtual_tryon/testing/reference_shape.h"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <functional>
#include <string>
#include <vector>

namespace vt = virtual_tryon;

namespace {

struct Method {
  const char* name;
  std::function<std::string(const vt::Body&, vt::TriMesh&)> run;  // returns a short status
};

std::string resolveWith(const vt::Body& body, vt::TriMesh& g, vt::ResolverObjective objective, vt::ZoneSolver solver) {
  vt::ResolverParams p;
  p.objective = objective;
  p.solver = solver;
  const vt::ResolverReport rep = vt::resolvePenetrations(body, g, p);
  char s[96];
  std::snprintf(s, sizeof s, "%s, %d it", rep.converged ? "converged" : "NOT converged", rep.iterations);
  return s;
}

std::vector<Method> methods() {
  using vt::ResolverObjective;
  using vt::ZoneSolver;
  return {
      {"ours (smooth)", [](const vt::Body& b, vt::TriMesh& g) { return resolveWith(b, g, ResolverObjective::Smooth, ZoneSolver::ImpactZone); }},
      {"paper", [](const vt::Body& b, vt::TriMesh& g) { return resolveWith(b, g, ResolverObjective::Paper, ZoneSolver::ImpactZone); }},
      {"per-stencil projection", [](const vt::Body& b, vt::TriMesh& g) { return resolveWith(b, g, ResolverObjective::Paper, ZoneSolver::PerStencilProjection); }},
      {"push-out baseline", [](const vt::Body& b, vt::TriMesh& g) { vt::pushOutBaseline(b, g); return std::string("-"); }},
  };
}

}  // namespace

int main(int argc, char** argv) {
  virtual_tryon::keepHeapForFrames();
  std::string dir = argc > 1 ? argv[1] : (std::getenv("VT_DATA") ? std::getenv("VT_DATA") : "../shared/data");
  const int runs = argc > 2 ? std::max(1, std::atoi(argv[2])) : 15;
  vt::TriMesh bodyMesh;
  std::string err;
  if (!vt::readMesh(dir + "/body_hm08.obj", bodyMesh, err)) {
    std::printf("resolve_benchmark: no shared data at '%s' (%s); skipping\n", dir.c_str(), err.c_str());
    return 0;
  }
  vt::Body body(bodyMesh);
  body.bvh();
  const vt::ReferenceReferee referee(bodyMesh);
  std::printf("body_hm08: %ld vertices, %ld faces, closed=%d, BVH build %.2f ms\n\n",
              static_cast<long>(bodyMesh.V.rows()), static_cast<long>(bodyMesh.F.rows()), body.closed(),
              1e3 * body.bvhBuildSeconds());
  std::printf("| garment | V | method | status | left: g-edge / b-edge / inside | strain max / p99 | max displacement / need (mm) | far vertices moved | median (min-max) ms |\n");
  std::printf("|---|---|---|---|---|---|---|---|---|\n");
  const char* garments[] = {"tshirt_female_casualsuit01_top", "trousers_jeans_female_casualsuit01",
                            "tshirt_male_casualsuit04", "skirt_female_elegantsuit01"};
  int failures = 0;
  for (const char* name : garments) {
    vt::TriMesh g0;
    if (!vt::readMesh(dir + "/" + name + ".obj", g0, err)) {
      std::printf("| %s | missing: %s |\n", name, err.c_str());
      continue;
    }
    bool first = true;
    for (const Method& m : methods()) {
      std::vector<double> ms;
      vt::TriMesh out;
      std::string status;
      for (int r = 0; r < runs; ++r) {
        vt::TriMesh g = g0;
        const auto t0 = std::chrono::steady_clock::now();
        status = m.run(body, g);
        ms.push_back(1e3 * std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
        out = g;
      }
      std::sort(ms.begin(), ms.end());
      const vt::ReferenceCounts c = referee.count(out);
      const vt::ReferenceShape s = vt::referenceShape(referee, g0, out, body.closed());
      if (first && c.garment_edge_crossings + c.body_edge_crossings + c.vertices_inside > 0) ++failures;
      std::printf("| %s | %ld | %s | %s | %zu / %zu / %zu | %.3f / %.3f | %.1f / %.1f | %zu | %.2f (%.2f-%.2f) |\n",
                  first ? name : "", static_cast<long>(g0.V.rows()), m.name, status.c_str(),
                  c.garment_edge_crossings, c.body_edge_crossings, c.vertices_inside, s.max_strain, s.p99_strain,
                  1e3 * s.max_displacement, 1e3 * s.need, s.far_vertices_moved, ms[ms.size() / 2], ms.front(),
                  ms.back());
      first = false;
    }
  }
  std::printf("\n%d garments left with crossings or inside vertices by our method\n", failures);
  return failures == 0 ? 0 : 1;
}
