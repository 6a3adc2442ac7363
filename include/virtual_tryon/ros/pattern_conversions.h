// Conversions between virtual_tryon/GarmentPattern messages (with their Panel and Seam messages)
// and the core's Pattern (PatternPanel, PatternSeam). Plain functions, no state.
#pragma once

#include "virtual_tryon/core/drape/pattern.h"
#include <virtual_tryon/GarmentPattern.h>

#include <geometry_msgs/Pose.h>
#include <std_msgs/Header.h>

#include <Eigen/Geometry>

#include <string>

namespace virtual_tryon {
namespace ros_conversions {

// Pose -> isometry. The quaternion is normalized; a quaternion with a non-finite component or a
// norm below 1e-9 (e.g. the all-zero default of an unset Pose) fails, as does a non-finite
// position. On failure `out` is left unchanged and `error` says what is wrong (no prefix).
bool poseToIsometry(const geometry_msgs::Pose& pose, Eigen::Isometry3d& out, std::string& error);
// Isometry -> pose (rotation as a unit quaternion with w >= 0).
geometry_msgs::Pose isometryToPose(const Eigen::Isometry3d& pose);

// Message -> core. Panels: outline_u[i], outline_v[i] give outline point i (the two arrays must
// have the same length), pose -> placement.pose as above, wrap_radius copied. Seams: panel_a,
// a_from, a_to -> a = {panel, from, to}, likewise b (indices must fit an int). Errors name the
// panel ("panel 'front' (index 0): outline_u has 4 values but outline_v has 3") or the seam
// ("seam 2: ..."). The geometry is not checked here (outline shape, indices in range, stretch
// lengths): run validatePattern on the result. On failure `pattern` is left unchanged.
// The header (frame) is not part of the core pattern; read msg.header.frame_id yourself.
bool fromMsg(const GarmentPattern& msg, Pattern& pattern, std::string& error);

// Core -> message with `header`; exact inverse of fromMsg for a pattern with non-negative seam
// indices (negative ones, which no valid pattern has, become 0).
GarmentPattern toMsg(const Pattern& pattern, const std_msgs::Header& header);

}  // namespace ros_conversions
}  // namespace virtual_tryon
