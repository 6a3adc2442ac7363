// Core reports -> virtual_tryon/BodyReport, virtual_tryon/PenetrationReport and
// virtual_tryon/DrapeReport messages. Plain functions, no state.
#pragma once

#include "virtual_tryon/core/body/body_check.h"
#include "virtual_tryon/core/drape/collider.h"
#include "virtual_tryon/core/drape/drape.h"
#include "virtual_tryon/core/drape/worn_garment.h"
#include "virtual_tryon/core/resolve/penetration_resolver.h"
#include <virtual_tryon/BodyReport.h>
#include <virtual_tryon/DrapeReport.h>

#include <virtual_tryon/PenetrationReport.h>

#include <string>

namespace virtual_tryon {
namespace ros_conversions {

// The check's fields (counts clamped to uint32; components = pieces, summary as written) with
// `source` ("mesh" or "scan"); the scan fields are left 0 for the caller to fill.
virtual_tryon::BodyReport toMsg(const BodyCheck& check, const std::string& source);

// Field-by-field copy; counts are clamped to the uint32 range of the message.
virtual_tryon::PenetrationReport toMsg(const ResolverReport& report);

// Field-by-field copy (counts clamped to uint32, the resolver report nested); the core report
// does not record the collision mode, so it is given: collision_mode = collisionModeName(mode).
DrapeReport toMsg(const DrapeResult& report, CollisionMode mode);

// One frame of a worn garment (WornGarment::follow) as a drape report: steps as iterations, the
// cloth's time as the simulation's, strain_max after the steps and strain_max_final after the
// resolver, whose report is nested; image space. `garment`: the garment as returned.
DrapeReport toMsg(const WornFrameReport& report, const TriMesh& garment);

// "image" / "object".
std::string collisionModeName(CollisionMode mode);
// "image" or "object" (exactly, lower case) -> mode; false for anything else (mode unchanged).
bool parseCollisionMode(const std::string& name, CollisionMode& mode);

}  // namespace ros_conversions
}  // namespace virtual_tryon
