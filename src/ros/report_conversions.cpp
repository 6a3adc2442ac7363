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

virtual_tryon::BodyReport toMsg(const BodyCheck& check, const std::string& source) {
  virtual_tryon::BodyReport m;
  m.source = source;
  m.vertices = u32(check.vertices);
  m.faces = u32(check.faces);
  m.closed = check.closed;
  m.boundary_edges = u32(check.boundary_edges);
  m.non_manifold_edges = u32(check.non_manifold_edges);
  m.degenerate_faces = u32(check.degenerate_faces);
  m.components = u32(check.pieces);
  m.signed_volume = check.signed_volume;
  m.flipped = check.flipped;
  m.summary = check.summary;
  return m;
}

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
  m.body_uncertainty = r.body_uncertainty;
  m.near_vertices_pushed = static_cast<std::uint32_t>(r.near_vertices_pushed);
  m.mean_displacement = r.mean_displacement;
  m.max_displacement = r.max_displacement;
  m.max_edge_strain = r.max_edge_strain;
  m.p99_edge_strain = r.p99_edge_strain;
  m.objective = r.objective;
  m.relaxed = r.relaxed;
  m.relaxation_sweeps = static_cast<std::uint32_t>(r.relaxation.sweeps);
  m.seconds_relaxation = r.seconds_relaxation;
  m.time_budget_spent = r.time_budget_spent;
  m.max_condition_estimate = r.max_condition_estimate;
  m.seconds_detection = r.seconds_detection;
  m.seconds_solve = r.seconds_solve;
  m.seconds_total = r.seconds_total;
  return m;
}

DrapeReport toMsg(const DrapeResult& r, CollisionMode mode) {
  DrapeReport m;
  m.converged = r.converged;
  m.cancelled = r.cancelled;
  m.message = r.message;
  m.warnings = r.warnings;
  m.vertices = u32(r.vertices);
  m.triangles = u32(r.triangles);
  m.iterations = u32(r.iterations);
  m.sew_iterations = u32(r.sew_iterations);
  m.dt = r.dt;
  m.dt_bound = r.dt_bound;
  m.dt_bound_paper = r.dt_bound_paper;
  m.collision_mode = collisionModeName(mode);
  m.map_size = u32(r.map_size);
  m.seconds_setup = r.seconds_setup;
  m.seconds_simulation = r.seconds_simulation;
  m.seconds_per_iteration = r.seconds_per_iteration;
  m.seconds_resolve = r.seconds_resolve;
  m.seconds_total = r.seconds_total;
  m.seams_total = u32(r.seams_total);
  m.seams_open = u32(r.seams_open);
  m.seam_gap_max = r.seam_gap_max;
  m.seam_gap_mean = r.seam_gap_mean;
  m.strain_max = r.strain_max;
  m.strain_mean = r.strain_mean;
  m.strain_max_final = r.strain_max_final;
  m.boundary_loops = u32(r.boundary_loops);
  for (const DrapeResult::SeamLength& l : r.seam_lengths) {
    m.seam_length_a.push_back(l.a);
    m.seam_length_b.push_back(l.b);
    m.seam_take_in.push_back(l.take_in);
  }
  m.seam_take_in_max = r.seam_take_in_max;
  m.openings = u32(r.openings);
  m.max_speed = r.max_speed;
  m.kinetic_energy = r.kinetic_energy;
  m.penetrating_before_resolve = u32(r.penetrating_before_resolve);
  m.penetrating_after = u32(r.penetrating_after);
  m.resolver_run = r.resolver_run;
  m.resolver = toMsg(r.resolver);
  return m;
}

DrapeReport toMsg(const WornFrameReport& r, const TriMesh& garment) {
  DrapeReport m;
  m.converged = r.converged;
  m.message = r.message;
  m.vertices = u32(static_cast<std::size_t>(garment.V.rows()));
  m.triangles = u32(static_cast<std::size_t>(garment.F.rows()));
  m.iterations = u32(r.steps);
  m.dt = r.dt;
  m.collision_mode = collisionModeName(CollisionMode::ImageSpace);
  m.seconds_simulation = r.seconds_cloth;
  m.seconds_resolve = r.seconds_resolve;
  m.seconds_total = r.seconds_total;
  m.strain_max = r.strain_stepped;
  m.strain_max_final = r.strain_max;
  m.max_speed = r.max_speed;
  m.resolver_run = r.resolver_run;
  if (r.resolver_run) m.resolver = toMsg(r.resolver);
  return m;
}

std::string collisionModeName(CollisionMode mode) {
  return mode == CollisionMode::ObjectSpace ? "object" : "image";
}

bool parseCollisionMode(const std::string& name, CollisionMode& mode) {
  if (name == "image") {
    mode = CollisionMode::ImageSpace;
    return true;
  }
  if (name == "object") {
    mode = CollisionMode::ObjectSpace;
    return true;
  }
  return false;
}

}  // namespace ros_conversions
}  // namespace virtual_tryon
