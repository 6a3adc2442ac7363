#include "virtual_tryon/core/scenes/demo_scene.h"

#include "virtual_tryon/core/scenes/procedural_body.h"
#include "virtual_tryon/core/scenes/synthetic_scan.h"

#include <algorithm>
#include <cmath>

namespace virtual_tryon {
namespace {

// Distance from `c` along the horizontal unit direction `d` to the body surface, by marching out of
// the body (c must be inside) and bisecting the first sign change.
double surfaceRadius(const Eigen::Vector3d& c, const Eigen::Vector3d& d) {
  const double step = 0.005;
  double inside = 0, r = step;
  while (r < 0.6 && proceduralBodySdf(c + r * d) < 0) {
    inside = r;
    r += step;
  }
  double lo = inside, hi = r;
  for (int i = 0; i < 30; ++i) {
    const double mid = 0.5 * (lo + hi);
    (proceduralBodySdf(c + mid * d) < 0 ? lo : hi) = mid;
  }
  return 0.5 * (lo + hi);
}

}  // namespace

TriMesh makeWrinkledWaistTube(double y0, double y1, int segments, int rings, double gap, double dip) {
  const ProceduralBodyLandmarks L = proceduralBodyLandmarks();
  const double kPi = 3.14159265358979323846;
  TriMesh m;
  m.V.resize(static_cast<Eigen::Index>(segments) * rings, 3);
  for (int r = 0; r < rings; ++r) {
    const double t = rings > 1 ? double(r) / (rings - 1) : 0.0;
    const double y = y0 + t * (y1 - y0);
    // Section centre: between the waist's and the chest's, by height.
    const double u = std::clamp((y - L.waist_y) / (L.chest_y - L.waist_y), 0.0, 1.0);
    const Eigen::Vector3d c(0, y, (1 - u) * L.waist_z + u * L.chest_z);
    for (int s = 0; s < segments; ++s) {
      const double a = 2 * kPi * s / segments;
      const Eigen::Vector3d d(std::sin(a), 0, std::cos(a));
      // Folds: a few soft vertical pleats, strongest mid-height.
      const double pleat = std::pow(std::max(0.0, std::sin(5 * a + 2.0 * t)), 2);
      const double fold = pleat * std::sin(kPi * t);
      m.V.row(r * segments + s) = (c + (surfaceRadius(c, d) + gap - dip * fold) * d).transpose();
    }
  }
  m.F.resize(2 * static_cast<Eigen::Index>(segments) * (rings - 1), 3);
  Eigen::Index f = 0;
  for (int r = 0; r + 1 < rings; ++r)
    for (int s = 0; s < segments; ++s) {
      const int s1 = (s + 1) % segments;
      const int a = r * segments + s, b = r * segments + s1;
      const int c = (r + 1) * segments + s, e = (r + 1) * segments + s1;
      // Counter-clockwise seen from outside (angle grows from +z towards +x, height along +y).
      m.F.row(f++) << a, b, c;
      m.F.row(f++) << b, e, c;
    }
  return m;
}

DemoScene makeDemoScene(const DemoSceneParams& params) {
  DemoScene scene;
  scene.body = makeProceduralBody();
  SyntheticScanParams sp;
  sp.points = params.scan_points;
  sp.noise_sigma = params.scan_noise;
  sp.seed = params.seed;
  scene.scan = syntheticScan(scene.body, sp).points;
  const ProceduralBodyLandmarks L = proceduralBodyLandmarks();
  scene.garment = makeWrinkledWaistTube(L.waist_y - 0.10, L.waist_y + 0.12, params.garment_segments,
                                        params.garment_rings, params.garment_gap, params.garment_dip);
  return scene;
}

}  // namespace virtual_tryon
