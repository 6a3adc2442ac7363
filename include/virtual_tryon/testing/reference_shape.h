// The referee's shape measures: how far a resolver moved a garment and how much it stretched it,
// against the least move that any resolver must make. Independent of the resolver (the referee's
// own trees and predicates, reference_bvh.h), for tests, benchmarks, the evaluation and
// `tryon check --reference INPUT`.
#pragma once

#include "virtual_tryon/core/geometry/mesh.h"
#include "virtual_tryon/testing/reference_bvh.h"

#include <cstddef>
#include <string>

namespace virtual_tryon {

struct ReferenceShapeParams {
  double far_distance = 0.01;     // a vertex that started farther than this from the body (m) ...
  double moved_distance = 0.001;  // ... and moved more than this (m) counts as a far vertex moved
};

struct ReferenceShape {
  std::size_t edges = 0;          // edges of the input garment with non-zero length
  double max_strain = 0;          // largest |l / l0 - 1| over those edges, l0 input, l output length
  double p99_strain = 0;          // its 99th percentile (nearest rank)
  double mean_displacement = 0;   // over every vertex, metres
  double max_displacement = 0;
  std::size_t moved_vertices = 0;  // vertices that moved at all
  // The need: the least lift that any resolver must make, the larger of
  //   need_inside: the deepest input vertex inside the (closed) body, its distance to the surface;
  //   need_body_edges: over every body edge that crosses an input garment face, the distance from
  //     that face's plane to the edge's outer end (the end the body's outward normal points to),
  //     which the face must pass.
  double need = 0;
  double need_inside = 0;
  double need_body_edges = 0;
  std::size_t far_vertices_moved = 0;  // see ReferenceShapeParams
};

// `input` and `output` share faces and vertex order (#V x 3 each). `closedBody`: count inside
// vertices for need_inside (an open body has no inside). Cost: one signed distance per input
// vertex and one tree query per body edge.
ReferenceShape referenceShape(const ReferenceReferee& referee, const TriMesh& input, const TriMesh& output,
                              bool closedBody, const ReferenceShapeParams& params = ReferenceShapeParams());

// The measures as one JSON object (lengths in metres, keys with _m).
std::string toJson(const ReferenceShape& shape);

}  // namespace virtual_tryon
