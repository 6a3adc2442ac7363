#include "virtual_tryon/ros/report_conversions.h"

#include <algorithm>
#include <cstdint>
#include <limits>

namespace virtual_tryon {
namespace ros_conversions {
namespace {

std::uint32_t u32(std::size_t n) {
  return static_cast<std::uint32_t>(
      std::min<std::size_t>(n, std::numeric_limits<std::uint32_t>::max()));
}

std::uint32_t u32(int n) { return n < 0 ? 0u : u32(static_cast<std::size_t>(n)); }

}  // namespace

virtual_tryon::PenetrationReport toMsg(const ResolverReport& r) {
  virtual_tryon::PenetrationReport m;
  m.converged = r.converged;
  m.reason = r.reason;
  m.iterations = u32(r.iterations);
  m.garment_edge_crossings_before = u32(r.garment_edge_crossings_before);
  m.body_edge_crossings_before = u32(r.body_edge_crossings_before);
  m.garment_edge_crossings_after = u32(r.garment_edge_crossings_after);
  m.body_edge_crossings_after = u32(r.body_edge_crossings_after);
  m.illegal_vertices = u32(r.illegal_vertices);
  m.impact_zones = u32(r.impact_zones);
  m.infeasible_zones = u32(r.infeasible_zones);
  m.vertices_inside_before = u32(r.vertices_inside_before);
  m.vertices_inside_after = u32(r.vertices_inside_after);
  m.body_closed = r.body_closed;
  m.moved_vertices = u32(r.moved_vertices);
  m.clearance = r.clearance;
  m.mean_displacement = r.mean_displacement;
  m.max_displacement = r.max_displacement;
  m.seconds_detection = r.seconds_detection;
  m.seconds_solve = r.seconds_solve;
  m.seconds_total = r.seconds_total;
  return m;
}

}  // namespace ros_conversions
}  // namespace virtual_tryon
