// A baseline for the evaluation, not a method of either paper: the vertex push-out that learned
// garment models apply after inference (e.g. DRAPE, Guan et al. 2012, which Sun et al. 2016
// discuss). Every garment vertex found inside the body moves to its nearest body point plus a
// margin along the normal of the body face that point lies on. Vertex only: no edge is tested, so
// garment edges through body faces and body edges through garment faces may stay.
#pragma once

#include "virtual_tryon/core/body/body.h"
#include "virtual_tryon/core/geometry/mesh.h"

#include <cstddef>

namespace virtual_tryon {

struct PushOutParams {
  // Margin in metres; <= 0 means margin_fraction * mean garment edge length (the resolver's
  // default clearance, so both leave the same gap).
  double margin = 0.0;
  double margin_fraction = 0.05;
};

struct PushOutReport {
  bool body_closed = false;
  std::size_t vertices_inside = 0;  // found inside and moved
  double margin = 0;
  double mean_displacement = 0;  // over moved vertices, metres
  double max_displacement = 0;
  double seconds_detection = 0;  // inside tests
  double seconds_total = 0;
};

// Moves the inside vertices of `garment` (#V by 3; faces and vertex order unchanged). Inside: for
// a closed body the ray-parity test of point_queries.h; for an open body, behind the nearest
// face's plane ((x - p) . n < 0 with p the nearest point).
PushOutReport pushOutBaseline(const Body& body, TriMesh& garment, const PushOutParams& params = PushOutParams());

}  // namespace virtual_tryon
