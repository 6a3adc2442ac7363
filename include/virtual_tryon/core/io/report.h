// Reports as JSON text (one object, stable key order), for the CLI, the demo and benchmarks.
#pragma once

#include "virtual_tryon/core/drape/drape.h"
#include "virtual_tryon/core/resolve/penetration_resolver.h"

#include <string>

namespace virtual_tryon {

std::string toJson(const ResolverReport& report);
// Every DrapeResult field (units in the key: _m, _s, _m_per_s, _j); the resolver's report nested
// as "resolver": {...} when it ran, else "resolver": null.
std::string toJson(const DrapeResult& report);

}  // namespace virtual_tryon
