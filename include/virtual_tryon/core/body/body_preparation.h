// One preparation for every body that comes in (a mesh file, a mesh message, a meshed scan): the
// mesh is validated once (validate()), analysed once (body_check.h: pieces, edge topology,
// volumes, orientation) and, under the caller's policy, an inside-out body is flipped back or
// refused. The node flips (a scanner's winding is not its user's doing); the `tryon` command
// refuses, so that a batch run never changes its input behind the user's back.
//
// The body's warnings and its refusal, after flipping when the policy flips:
// - those of validate(mesh, "body") (degenerate or duplicate faces, duplicate or unused vertices,
//   a size that suggests millimetres);
// - an open or non-manifold body: the resolver then cannot test whether garment pieces lie inside;
// - more than one piece;
// - a closed body whose signed volume (from the origin, as signedVolume()) is negative is inside
//   out, which is fatal (the resolver would push the garment in); a closed body that encloses no
//   volume, or with pieces of negative volume, is a warning.
#pragma once

#include "virtual_tryon/core/body/body_check.h"
#include "virtual_tryon/core/geometry/mesh.h"

#include <string>
#include <vector>

namespace virtual_tryon {

// What prepareBody does with a body whose pieces are inside out.
enum class InsideOutPolicy {
  Flip,    // reverse the winding of every inverted piece (as orientBody), then check what is left
  Refuse,  // leave the mesh as it is; a closed body whose signed volume is negative is refused
};

struct BodyPreparationParams {
  MeshLimits limits;  // the size a body may have (validate())
  InsideOutPolicy policy = InsideOutPolicy::Flip;
  double open_flip_ratio = 0.5;  // BodyCheckParams::open_flip_ratio
};

struct BodyPreparation {
  bool ok = false;    // false: refused, see `error`
  std::string error;  // why: the mesh is unusable (check.ok == false: validate()'s message), or
                      // the body is inside out ("body is inside out: its signed volume is ...")
  TriMesh mesh;       // the body, oriented: Flip: the inverted pieces flipped back; Refuse: as given
  MeshValidation validation;  // validate(mesh, "body", limits) of the mesh as given
  BodyCheck check;    // checkBody (Refuse) or orientBody (Flip) of the mesh, with its summary
  // One sentence each, naming the body ("body has 2 separate pieces"); under Flip, when a piece was
  // flipped, first "body arrived inside out (inward normals) and was flipped". Empty when refused.
  std::vector<std::string> warnings;
  bool flipped = false;  // Flip reversed the winding of at least one piece (check.flipped)
};

// Validates, checks and orients `mesh` as a body under `params` (see above).
BodyPreparation prepareBody(TriMesh mesh, const BodyPreparationParams& params = BodyPreparationParams());

// The same for a mesh its caller has validated already: `validation` must be
// validate(mesh, "body", params.limits); it is not repeated.
BodyPreparation prepareBody(TriMesh mesh, MeshValidation validation, const BodyPreparationParams& params);

// prepareBody(mesh, {limits, Refuse}) as a MeshValidation: validate(mesh, "body")'s counts with the
// body's warnings (open, non-manifold, pieces, volume) and its refusal (inside out: ok false, the
// warnings cleared); `message` is the fatal problem or the warnings joined by "; ".
MeshValidation validateBody(const TriMesh& mesh, const MeshLimits& limits = MeshLimits());

}  // namespace virtual_tryon
