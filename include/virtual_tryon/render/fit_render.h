// Pictures of a fitted garment on its body: the fit map that try-on tools show, the garment
// coloured by how far its fabric is stretched (edge or spring strain |l / l0 - 1|), on a grey
// body, from the front, the side and the back. Rendered offscreen with VTK (OpenGL); VTK on
// Debian needs an X server, so without a display run it under `xvfb-run -a` (the `tryon render`
// command does this itself). Not part of the core: no algorithm depends on it.
#pragma once

#include "virtual_tryon/core/geometry/mesh.h"

#include <string>
#include <vector>

namespace virtual_tryon {

struct FitRenderParams {
  int width = 700, height = 900;            // pixels of each picture
  Eigen::Vector3d up{0, 1, 0};              // the meshes' up axis (MakeHuman and ours: +y)
  Eigen::Vector3d front{0, 0, 1};           // the way the body faces
  double strain_scale = 0.15;               // strain shown at the top of the colour scale (red)
  std::vector<std::string> views{"front", "side", "back"};  // of "front", "side", "back"
  std::string title;                        // shown above each picture, e.g. the garment's name
};

struct FitRenderResult {
  bool success = false;
  std::string message;             // why not, on failure
  std::vector<std::string> files;  // the PNGs written, in the order of params.views
  double seconds = 0;
};

// Writes OUT_PREFIX_VIEW.png for each view: `body` (#V by 3, #F by 3; may be empty) in grey and
// `garment` coloured by `vertex_strain` (#V of the garment, from 0 at blue to strain_scale and
// beyond at red; empty: the garment in one colour). Never throws.
FitRenderResult renderFit(const TriMesh& body, const TriMesh& garment, const std::vector<double>& vertex_strain,
                          const std::string& out_prefix, const FitRenderParams& params = FitRenderParams());

}  // namespace virtual_tryon
