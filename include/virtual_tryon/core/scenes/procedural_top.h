// A top cut from the procedural body's own surface: the skin meshed at `garmentResolution`,
// pushed out along its normals by 3 mm plus a 12 mm wave (five folds round the body, one every
// 12 cm in height), so that the folds dip about 1 cm into the body, and kept between the hips and
// 60% of the way from the waist to the chest (the largest connected piece). Marching tetrahedra
// leave sliver triangles and edges a fraction of a millimetre long, which any tangential move
// stretches many times over: a hard case for the resolver's shape. The body is the procedural body
// at `bodyResolution`.
#pragma once

#include "virtual_tryon/core/scenes/procedural.h"

namespace virtual_tryon {

ResolveScene makeProceduralTopScene(double bodyResolution = 0.02, double garmentResolution = 0.03);

}  // namespace virtual_tryon
