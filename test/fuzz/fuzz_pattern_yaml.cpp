// libFuzzer target: the YAML pattern reader (parsePatternYaml, which runs validatePattern). A
// pattern that reads must write (patternToYaml) and read back to the same pattern, and is then
// meshed at a spacing of 1/12 of its largest panel (meshPattern).
#include "virtual_tryon/core/drape/pattern.h"
#include "virtual_tryon/core/io/pattern_yaml.h"

#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>

namespace vt = virtual_tryon;

namespace {

bool samePattern(const vt::Pattern& a, const vt::Pattern& b) {
  if (a.name != b.name || a.panels.size() != b.panels.size() || a.seams.size() != b.seams.size()) return false;
  for (std::size_t i = 0; i < a.panels.size(); ++i) {
    const vt::PatternPanel &p = a.panels[i], &q = b.panels[i];
    if (p.name != q.name || p.outline != q.outline || p.placement.wrap_radius != q.placement.wrap_radius) return false;
    if (!(p.placement.pose.translation() == q.placement.pose.translation())) return false;
    if (!p.placement.pose.linear().isApprox(q.placement.pose.linear(), 1e-12)) return false;
  }
  for (std::size_t k = 0; k < a.seams.size(); ++k) {
    const vt::PatternSeam &s = a.seams[k], &t = b.seams[k];
    if (s.a.panel != t.a.panel || s.a.from != t.a.from || s.a.to != t.a.to || s.b.panel != t.b.panel ||
        s.b.from != t.b.from || s.b.to != t.b.to || s.stage != t.stage)
      return false;
  }
  return true;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  vt::Pattern pattern;
  std::string error;
  if (!vt::parsePatternYaml(text, pattern, error)) {
    if (error.empty()) std::abort();
    return 0;
  }
  if (!vt::validatePattern(pattern).empty()) std::abort();  // the reader validates
  const std::string yaml = vt::patternToYaml(pattern);
  vt::Pattern back;
  if (!vt::parsePatternYaml(yaml, back, error) || !samePattern(pattern, back)) {
    std::fprintf(stderr, "round trip failed: %s\n--- written ---\n%s\n", error.c_str(), yaml.c_str());
    std::abort();
  }
  double extent = 0;
  for (const vt::PatternPanel& p : pattern.panels)
    extent = std::max(extent, (p.outline.colwise().maxCoeff() - p.outline.colwise().minCoeff()).maxCoeff());
  vt::Pattern normalized = pattern;
  vt::normalizePattern(normalized);
  vt::ClothMesh cloth;
  vt::MeshLimits limits;
  limits.max_vertices = 20000;
  if (vt::meshPattern(normalized, std::max(extent / 12, 1e-3), cloth, error, limits)) {
    for (const vt::SeamPair& s : cloth.seam_pairs)
      if (s.a < 0 || s.b < 0 || s.a >= cloth.X.rows() || s.b >= cloth.X.rows()) std::abort();
    for (const vt::Spring& s : cloth.springs)
      if (s.a < 0 || s.b < 0 || s.a >= cloth.X.rows() || s.b >= cloth.X.rows()) std::abort();
  } else if (error.empty()) {
    std::abort();
  }
  return 0;
}
