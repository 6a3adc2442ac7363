// Resolver benchmark on the shared MakeHuman meshes: body_hm08 with each garment.
// Usage: resolve_benchmark [DATA_DIR] [RUNS]   (DATA_DIR default: ../shared/data, or $VT_DATA)
// Prints one Markdown table; skips (exit 0) when the data is absent.
#include "virtual_tryon/core/body/body.h"
#include "virtual_tryon/core/io/mesh_io.h"
#include "virtual_tryon/core/resolve/penetration_resolver.h"
#include "virtual_tryon/testing/reference_check.h"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

namespace vt = virtual_tryon;

int main(int argc, char** argv) {
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
  std::printf("body_hm08: %ld vertices, %ld faces, closed=%d, BVH build %.2f ms\n\n",
              static_cast<long>(bodyMesh.V.rows()), static_cast<long>(bodyMesh.F.rows()), body.closed(),
              1e3 * body.bvhBuildSeconds());
  std::printf("| garment | V | crossings before (g-edge/b-edge) | after (resolver) | after (independent) | inside before -> after (independent) | iterations | mean / max displacement (mm) | resolve median (min-max) ms | detection / solve ms |\n");
  std::printf("|---|---|---|---|---|---|---|---|---|---|\n");
  const char* garments[] = {"tshirt_female_casualsuit01_top", "trousers_jeans_female_casualsuit01",
                            "tshirt_male_casualsuit04", "skirt_female_elegantsuit01"};
  int failures = 0;
  for (const char* name : garments) {
    vt::TriMesh g0;
    if (!vt::readMesh(dir + "/" + name + ".obj", g0, err)) {
      std::printf("| %s | missing: %s |\n", name, err.c_str());
      continue;
    }
    const vt::ReferenceCounts before = vt::referenceCounts(bodyMesh, g0);
    std::vector<double> ms;
    vt::ResolverReport rep;
    vt::TriMesh out;
    for (int r = 0; r < runs; ++r) {
      vt::TriMesh g = g0;
      const auto t0 = std::chrono::steady_clock::now();
      rep = vt::resolvePenetrations(body, g);
      ms.push_back(1e3 * std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
      out = g;
    }
    std::sort(ms.begin(), ms.end());
    const vt::ReferenceCounts after = vt::referenceCounts(bodyMesh, out);
    const bool clean = after.garment_edge_crossings + after.body_edge_crossings + after.vertices_inside == 0;
    if (!rep.converged || !clean) ++failures;
    std::printf("| %s | %ld | %zu / %zu | %zu / %zu | %zu / %zu | %zu -> %zu | %d | %.2f / %.2f | %.2f (%.2f-%.2f) | %.2f / %.2f |\n",
                name, static_cast<long>(g0.V.rows()), before.garment_edge_crossings, before.body_edge_crossings,
                rep.garment_edge_crossings_after, rep.body_edge_crossings_after, after.garment_edge_crossings,
                after.body_edge_crossings, before.vertices_inside, after.vertices_inside, rep.iterations,
                1e3 * rep.mean_displacement, 1e3 * rep.max_displacement, ms[ms.size() / 2], ms.front(),
                ms.back(), 1e3 * rep.seconds_detection, 1e3 * rep.seconds_solve);
  }
  std::printf("\n%d garments not resolved to zero\n", failures);
  return failures == 0 ? 0 : 1;
}
