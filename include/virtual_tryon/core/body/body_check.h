// Checks a body mesh as it arrives from a scanner (closed or open, boundary and non-manifold edges,
// degenerate faces, orientation by signed volume) and flips inverted pieces back to outward.
//
// How the orientation is decided, per connected piece (pieces connected over shared vertices):
// - A closed piece (no boundary edge, no non-manifold edge) whose faces are consistently wound
//   (every edge traversed once in each direction) encloses a volume whose sign is exact: it is
//   inverted when its signed volume is negative, outward when positive.
// - Any other piece (open, non-manifold, or inconsistently wound) gives only a hint: its signed
//   volume is measured from the centre of its bounding box and compared with its absolute volume
//   (the sum of |tetrahedron volumes| from that centre). It counts as inverted only when
//   signed <= -open_flip_ratio * absolute (clearly negative), as outward when
//   signed >= +open_flip_ratio * absolute, and as unclear in between (a flat patch through its own
//   centre, say, or a mix of windings); an unclear piece is never flipped.
// Flipping reverses the winding of every face of an inverted piece. A cavity (an inner shell
// wound inward on purpose) would be flipped too: bodies have none.
#pragma once

#include "virtual_tryon/core/geometry/mesh.h"

#include <cstddef>
#include <string>

namespace virtual_tryon {

struct BodyCheckParams {
  // For pieces that are not closed and consistently wound: the signed/absolute volume ratio
  // beyond which the orientation counts as known (see above). In (0, 1].
  double open_flip_ratio = 0.5;
  MeshLimits limits;  // the size a body may have (validate())
};

enum class BodyOrientation {
  Outward,   // every piece outward (or unclear pieces mixed with outward ones, see `unclear_pieces`)
  Inverted,  // at least one piece inverted (before flipping)
  Unclear,   // no piece has a clear orientation
};

// What checkBody / orientBody found (and did). The counts describe the mesh as given, except
// `signed_volume` and `orientation` after orientBody, which describe the mesh as returned.
struct BodyCheck {
  bool ok = false;      // false: unusable mesh (empty, non-finite, indices out of range); see message
  std::string message;  // the fatal problem, or "" when ok
  std::string summary;  // one line, e.g. "closed, 1 piece, 0 boundary edges, 0 non-manifold edges,
                        // 12 degenerate faces, volume 0.065 m^3, inverted: flipped"
  std::size_t vertices = 0, faces = 0;
  std::size_t pieces = 0;              // connected components over shared vertices
  bool closed = false;                 // no boundary and no non-manifold edge
  std::size_t boundary_edges = 0;      // edges with one incident face
  std::size_t non_manifold_edges = 0;  // edges with more than two incident faces
  std::size_t inconsistent_edges = 0;  // two-face edges traversed in the same direction by both
  std::size_t degenerate_faces = 0;    // repeated index or zero area (validate())
  std::size_t unused_vertices = 0;
  double signed_volume = 0;            // m^3, sum over the pieces (each from its box centre)
  BodyOrientation orientation = BodyOrientation::Unclear;
  std::size_t inverted_pieces = 0;     // found inverted
  std::size_t unclear_pieces = 0;      // orientation only hinted and not clear
  bool flipped = false;                // orientBody reversed the winding of the inverted pieces
  std::size_t flipped_faces = 0;
  double seconds = 0;
};

// Checks `mesh` (#V by 3, #F by 3) without changing it.
BodyCheck checkBody(const TriMesh& mesh, const BodyCheckParams& params = BodyCheckParams());

// Checks `mesh` and reverses the winding of every face of each inverted piece in place, so that a
// globally inverted body comes back outward. The result says what was flipped (`flipped`,
// `flipped_faces`, "inverted: flipped" in the summary); its volume and orientation are those of
// the mesh after flipping. An unusable mesh (ok == false) is left unchanged.
BodyCheck orientBody(TriMesh& mesh, const BodyCheckParams& params = BodyCheckParams());

// Reverses the winding of every face (swaps columns 1 and 2 of F, #F by 3).
void flipFaces(TriMesh& mesh);

}  // namespace virtual_tryon
