// The texts a fit's user reads, shared by every interface: a resolve in one line, the warnings
// about the inputs of a fit, and a drape's message, each as the node's responses carry them
// ("...; warning: ...").
#pragma once

#include "virtual_tryon/core/drape/collider.h"
#include "virtual_tryon/core/drape/drape.h"
#include "virtual_tryon/core/geometry/mesh.h"
#include "virtual_tryon/core/resolve/penetration_resolver.h"

#include <string>
#include <vector>

namespace virtual_tryon {

// "resolved 12 garment-edge + 3 body-edge crossings in 4 iterations (57 vertices moved, max
// 0.0123 m, clearance 0.002 m) in 0.052 s", or "not converged after 50 iterations: REASON (2
// garment-edge + 0 body-edge crossings left)" (at most 319 characters).
std::string resolveSummary(const ResolverReport& report);

// The warnings about the inputs of a resolve, in this order: the body's (found when it was
// prepared: flipped, degenerate or duplicate faces, open or non-manifold, several pieces, a size
// that suggests millimetres; prepareBody), the garment's (validate(garment, "garment", limits))
// and how the two are placed (placementWarnings).
std::vector<std::string> inputWarnings(const std::vector<std::string>& bodyWarnings, const TriMesh& body,
                                       const TriMesh& garment, const MeshLimits& limits);

// "; warning: W" for each of `warnings`, "" when none: what a response's message ends with.
std::string warningSuffix(const std::vector<std::string>& warnings);

// A drape's message: report.message, then "; warning: W" for each of `bodyWarnings` and then for
// each of report.warnings; for a drape that succeeded in image space (`mode`), whether the depth
// maps were rendered for it ("; depth maps rendered (N px)") or reused from the body's cache
// ("; depth maps reused (cached with the body)").
std::string drapeMessage(const DrapeResult& report, const std::vector<std::string>& bodyWarnings,
                         CollisionMode mode, bool mapsRendered);

}  // namespace virtual_tryon
