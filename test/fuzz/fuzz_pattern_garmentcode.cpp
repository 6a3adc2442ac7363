// libFuzzer target: the GarmentCode pattern specification reader (parseGarmentCodeJson, which runs
// validatePattern). A pattern that reads must validate, and is then meshed at a spacing of 1/12 of
// its largest panel (meshPattern).
#include "virtual_tryon/core/drape/pattern.h"
#include "virtual_tryon/core/io/pattern_garmentcode.h"

#include <algorithm>
#include <cstdint>
#include <cstdlib>
#include <string>

namespace vt = virtual_tryon;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  vt::Pattern pattern;
  vt::GarmentCodeReport report;
  std::string error;
  vt::GarmentCodeReadParams params;
  params.spacing = 0.05;
  if (!vt::parseGarmentCodeJson(text, params, pattern, report, error)) {
    if (error.empty()) std::abort();
    return 0;
  }
  if (!vt::validatePattern(pattern, 2.0).empty()) std::abort();  // the reader validates
  double extent = 0;
  for (const vt::PatternPanel& p : pattern.panels)
    extent = std::max(extent, (p.outline.colwise().maxCoeff() - p.outline.colwise().minCoeff()).maxCoeff());
  if (!(extent > 0)) return 0;
  vt::ClothMesh cloth;
  vt::MeshLimits limits;
  limits.max_vertices = 20000;
  meshPattern(pattern, extent / 12, cloth, error, limits);
  return 0;
}
