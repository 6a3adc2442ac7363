// Rigid motion of a pattern: an isometry (as tf2 gives between two frames) applied to where its
// panels start, so that a pattern given in one frame can be draped in another.
#pragma once

#include "virtual_tryon/core/drape/pattern.h"

#include <Eigen/Geometry>

namespace virtual_tryon {

// Moves every panel of `pattern` by T (placement.pose -> T * placement.pose, in place); the
// outlines, the wrap radii and the seams do not change.
inline void transformPattern(const Eigen::Isometry3d& T, Pattern& pattern) {
  for (PatternPanel& panel : pattern.panels) panel.placement.pose = T * panel.placement.pose;
}

}  // namespace virtual_tryon
