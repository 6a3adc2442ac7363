// The project's own demo scene, made without external files: the procedural body (about 1.7 m), a
// synthetic scan of it as a scanner gives it (points with noise, no normals), and a garment mesh
// placed with penetrations (a wrinkled tube round the waist whose folds dip into the body). The
// demo bag, the demo command and the replay rostest are built from it.
#pragma once

#include "virtual_tryon/core/geometry/mesh.h"

#include <cstddef>
#include <cstdint>

namespace virtual_tryon {

struct DemoSceneParams {
  std::size_t scan_points = 30000;  // samples of the synthetic scan
  double scan_noise = 0.002;        // m, standard deviation per coordinate
  std::uint64_t seed = 7;
  int garment_segments = 72;        // round the waist
  int garment_rings = 18;           // from below the waist to above it
  double garment_gap = 0.012;       // m, the tube's distance from the body where it does not dip
  double garment_dip = 0.028;       // m, depth of the folds below garment_gap (so up to 1.6 cm in)
};

struct DemoScene {
  TriMesh body;      // the procedural body mesh (closed, outward)
  MatrixX3d scan;    // #N by 3 scan points of the body
  TriMesh garment;   // #V by 3, #F by 3: an open tube, outward-facing, penetrating in its folds
};

DemoScene makeDemoScene(const DemoSceneParams& params = DemoSceneParams());

// The garment alone: a tube between heights y0 and y1 (metres) that follows the procedural body's
// cross-sections at `gap` from the surface, minus folds of depth `dip` (a smooth pattern over the
// angle and the height). Faces point away from the body.
TriMesh makeWrinkledWaistTube(double y0, double y1, int segments, int rings, double gap, double dip);

}  // namespace virtual_tryon
