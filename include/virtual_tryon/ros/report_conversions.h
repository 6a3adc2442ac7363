// Core ResolverReport -> virtual_tryon/PenetrationReport message. Plain function, no state.
#pragma once

#include "virtual_tryon/core/penetration_resolver.h"

#include <virtual_tryon/PenetrationReport.h>

namespace virtual_tryon {
namespace ros_conversions {

// Field-by-field copy; counts are clamped to the uint32 range of the message.
virtual_tryon::PenetrationReport toMsg(const ResolverReport& report);

}  // namespace ros_conversions
}  // namespace virtual_tryon
