// Internal to the core: the analysis behind checkBody, orientBody (body_check.h) and prepareBody
// (body_preparation.h), done once per body on a mesh that validate() accepted: pieces, the edge
// topology (boundary, non-manifold and inconsistently wound edges, from one pass over the
// half-edges), the volumes of each piece and its orientation; and the flip of the inverted pieces.
#pragma once

#include "virtual_tryon/core/body/body_check.h"
#include "virtual_tryon/core/geometry/mesh.h"

#include <vector>

namespace virtual_tryon {
namespace body_analysis {

struct PieceStats {
  bool open_or_nonmanifold = false;
  bool inconsistent = false;
  double signed_volume = 0;    // from the piece's box centre
  double absolute_volume = 0;  // sum of |tetrahedron volumes| from the same centre
  double origin_volume = 0;    // from the origin, as signedVolume() sums it (the body's warnings)
  int state = 0;               // +1 outward, -1 inverted, 0 unclear
};

struct BodyAnalysis {
  BodyCheck check;                  // without its summary (writeSummary) and time
  std::vector<int> face_piece;      // #F: the piece of each face
  std::vector<PieceStats> pieces;   // numbered in the order of their first face
  std::vector<int> component_piece;  // per connectedComponents() label: its piece, -1 without faces
};

// Analyses `mesh` given `validation` = validate(mesh, "body", params.limits). When the validation
// failed (or params.open_flip_ratio is out of range) check.ok is false, with the message and
// "unusable: ..." as the summary, and nothing else is filled.
BodyAnalysis analyse(const TriMesh& mesh, const MeshValidation& validation, const BodyCheckParams& params);

// Reverses the winding of every face of each inverted piece of an analysed mesh (check.ok, some
// piece inverted; otherwise nothing happens) and updates the analysis to the mesh as returned:
// the flipped pieces' volumes change sign, they count as outward, `flipped`, `flipped_faces`.
void flipInvertedPieces(TriMesh& mesh, BodyAnalysis& a);

// The one-line summary of a usable check (BodyCheck::summary); an unusable one keeps its own.
void writeSummary(BodyCheck& r);

}  // namespace body_analysis
}  // namespace virtual_tryon
