#include "virtual_tryon/core/body/body_preparation.h"

#include "core/body/body_analysis.h"
#include "core/geometry/wording.h"

#include <chrono>
#include <sstream>
#include <utility>

namespace virtual_tryon {
namespace {

using wording::metres;
using wording::plural;

// What a body needs beyond a usable mesh (see body_preparation.h), from the analysis of the mesh as
// it will be used: the warnings are appended to `warnings`; false with `error` when the body is
// inside out. `extent` is the longest side of its bounding box (validate()).
bool checkAsBody(const body_analysis::BodyAnalysis& a, double extent, std::vector<std::string>& warnings,
                 std::string& error) {
  const BodyCheck& c = a.check;
  if (c.boundary_edges > 0)
    warnings.push_back("body is open (" + plural(c.boundary_edges, "boundary edge", "boundary edges") +
                       "): garment pieces wholly inside it cannot be detected");
  if (c.non_manifold_edges > 0)
    warnings.push_back("body is non-manifold (" + plural(c.non_manifold_edges, "edge", "edges") +
                       " shared by more than two faces): garment pieces wholly inside it cannot be "
                       "detected");
  if (c.pieces > 1) warnings.push_back("body has " + std::to_string(c.pieces) + " separate pieces");
  if (!c.closed) return true;
  // The pieces' volumes from the origin, summed in the order of the connected components.
  double total = 0;
  std::size_t inverted = 0;
  for (int p : a.component_piece) {
    if (p < 0) continue;
    const double v = a.pieces[static_cast<std::size_t>(p)].origin_volume;
    total += v;
    inverted += v < 0;
  }
  const double tiny = 1e-12 * extent * extent * extent;
  if (total < -tiny) {
    error = "body is inside out: its signed volume is " + metres(total) +
            " m^3; faces must be wound counter-clockwise seen from outside (flip every face)";
    return false;
  }
  if (!(total > tiny))
    warnings.push_back("body encloses no volume (signed volume " + metres(total) + " m^3)");
  else if (inverted > 0)
    warnings.push_back("body has " + plural(inverted, "piece", "pieces") +
                       " with negative volume (inside out, or a cavity)");
  return true;
}

}  // namespace

BodyPreparation prepareBody(TriMesh mesh, const BodyPreparationParams& params) {
  MeshValidation validation = validate(mesh, "body", params.limits);
  return prepareBody(std::move(mesh), std::move(validation), params);
}

BodyPreparation prepareBody(TriMesh mesh, MeshValidation validation, const BodyPreparationParams& params) {
  const auto t0 = std::chrono::steady_clock::now();
  BodyCheckParams checkParams;
  checkParams.limits = params.limits;
  checkParams.open_flip_ratio = params.open_flip_ratio;
  body_analysis::BodyAnalysis a = body_analysis::analyse(mesh, validation, checkParams);
  if (params.policy == InsideOutPolicy::Flip) body_analysis::flipInvertedPieces(mesh, a);
  body_analysis::writeSummary(a.check);
  BodyPreparation out;
  out.flipped = a.check.flipped;
  if (!a.check.ok) {
    out.error = a.check.message;
  } else {
    if (out.flipped) out.warnings.push_back("body arrived inside out (inward normals) and was flipped");
    out.warnings.insert(out.warnings.end(), validation.warnings.begin(), validation.warnings.end());
    out.ok = checkAsBody(a, validation.extent, out.warnings, out.error);
    if (!out.ok) out.warnings.clear();
  }
  a.check.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  out.check = std::move(a.check);
  out.validation = std::move(validation);
  out.mesh = std::move(mesh);
  return out;
}

MeshValidation validateBody(const TriMesh& mesh, const MeshLimits& limits) {
  BodyPreparationParams params;
  params.limits = limits;
  params.policy = InsideOutPolicy::Refuse;
  const BodyPreparation prep = prepareBody(mesh, params);
  MeshValidation r = prep.validation;
  r.ok = prep.ok;
  r.warnings = prep.warnings;
  r.message = prep.error;
  for (const std::string& w : r.warnings) r.message += (r.message.empty() ? "" : "; ") + w;
  return r;
}

}  // namespace virtual_tryon
