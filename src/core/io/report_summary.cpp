#include "virtual_tryon/core/io/report_summary.h"

#include <cstdio>

namespace virtual_tryon {

std::string resolveSummary(const ResolverReport& r) {
  char buf[320], uncertainty[96] = "";
  if (r.body_uncertainty > 0)
    std::snprintf(uncertainty, sizeof uncertainty, ", of which %.4g m the body's uncertainty", r.body_uncertainty);
  if (r.converged)
    std::snprintf(buf, sizeof buf,
                  "resolved %zu garment-edge + %zu body-edge crossings in %d iterations "
                  "(%zu vertices moved, max %.4f m, clearance %.4g m%s) in %.3f s",
                  r.garment_edge_crossings_before, r.body_edge_crossings_before, r.iterations,
                  r.moved_vertices, r.max_displacement, r.clearance, uncertainty, r.seconds_total);
  else
    std::snprintf(buf, sizeof buf,
                  "not converged after %d iterations: %s (%zu garment-edge + %zu body-edge "
                  "crossings left)",
                  r.iterations, r.reason.c_str(), r.garment_edge_crossings_after,
                  r.body_edge_crossings_after);
  return buf;
}

std::vector<std::string> inputWarnings(const std::vector<std::string>& bodyWarnings, const TriMesh& body,
                                       const TriMesh& garment, const MeshLimits& limits) {
  std::vector<std::string> w = bodyWarnings;
  for (const std::string& g : validate(garment, "garment", limits).warnings) w.push_back(g);
  for (const std::string& g : placementWarnings(body, garment)) w.push_back(g);
  return w;
}

std::string warningSuffix(const std::vector<std::string>& warnings) {
  std::string s;
  for (const std::string& w : warnings) s += "; warning: " + w;
  return s;
}

std::string drapeMessage(const DrapeResult& report, const std::vector<std::string>& bodyWarnings,
                         CollisionMode mode, bool mapsRendered) {
  std::string message = report.message + warningSuffix(bodyWarnings) + warningSuffix(report.warnings);
  if (report.success && mode == CollisionMode::ImageSpace)
    message += mapsRendered ? "; depth maps rendered (" + std::to_string(report.map_size) + " px)"
                            : "; depth maps reused (cached with the body)";
  return message;
}

}  // namespace virtual_tryon
