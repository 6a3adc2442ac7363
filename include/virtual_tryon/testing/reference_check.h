// An independent referee for the resolver: brute-force counts that share no code with the
// resolver's detector (no FCL, no segmentCrossesTriangle). Every edge is tested against every
// face whose bounding box it overlaps, with a Moller-Trumbore segment-triangle test; inside is a
// ray-parity count over all faces. O(#E * #F): for tests, the CLI's `check` and benchmarks.
#pragma once

#include "virtual_tryon/core/geometry/mesh.h"

#include <cstddef>
#include <string>

namespace virtual_tryon {

struct ReferenceCounts {
  std::size_t garment_edge_crossings = 0;  // garment edges through body faces
  std::size_t body_edge_crossings = 0;     // body edges through garment faces
  std::size_t vertices_inside = 0;         // garment vertices inside the (closed) body
  double max_depth = 0;  // deepest inside vertex's distance to the body surface, metres
  std::size_t boundary_loops = 0;  // of the garment (referenceBoundaryLoops)
};

// The garment's boundary loops, found apart from the core's boundaryLoops(): every edge used by
// exactly one face, then the loops walked edge by edge (a depth-first search over the boundary
// edges that share a vertex). Two holes that share a vertex count as one.
std::size_t referenceBoundaryLoops(const TriMesh& garment);

// Counts proper crossings (the segment meets the triangle's interior at a parameter strictly
// between its end-points, up to `eps` relative to the edge length).
ReferenceCounts referenceCounts(const TriMesh& body, const TriMesh& garment, bool countInside = true,
                                double eps = 1e-12);

// The counts as one JSON object (keys as the fields; max_depth_m in metres).
std::string toJson(const ReferenceCounts& counts);

}  // namespace virtual_tryon
