// Reports as JSON text (one object, stable key order), for the CLI, the demo and benchmarks.
#pragma once

#include "virtual_tryon/core/penetration_resolver.h"
#include "virtual_tryon/core/reference_check.h"

#include <string>

namespace virtual_tryon {

std::string toJson(const ResolverReport& report);
std::string toJson(const ReferenceCounts& counts);

}  // namespace virtual_tryon
