#include "virtual_tryon/core/io/report.h"

#include "virtual_tryon/core/io/json_object.h"

#include <cmath>
#include <iomanip>
#include <sstream>
#include <string>
#include <vector>

namespace virtual_tryon {

using json::Obj;

namespace {

std::string toJson(const ShapeRelaxationReport& x, const ResolverReport& r) {
  if (!r.relaxed) return "null";
  return Obj()
      .add("max_edge_strain_before", r.max_edge_strain_before_relaxation)
      .add("active_vertices", x.active_vertices)
      .add("sweeps", x.sweeps)
      .add("steps_back", x.steps_back)
      .add("contacts", x.contacts)
      .add("plane_queries", x.plane_queries)
      .add("detections", x.detections)
      .add("faces_checked", x.faces_checked)
      .add("candidates_reused", x.candidates_reused)
      .add("seconds_checks", x.seconds_checks)
      .add("seconds_setup", x.seconds_setup)
      .add("seconds_rotations", x.seconds_rotations)
      .add("last_step_m", x.last_step)
      .add("clean", x.clean)
      .add("seconds", x.seconds)
      .str();
}

}  // namespace

std::string toJson(const ResolverReport& r) {
  return Obj()
      .add("converged", r.converged)
      .add("reason", r.reason)
      .add("iterations", r.iterations)
      .add("garment_edge_crossings_before", r.garment_edge_crossings_before)
      .add("body_edge_crossings_before", r.body_edge_crossings_before)
      .add("garment_edge_crossings_after", r.garment_edge_crossings_after)
      .add("body_edge_crossings_after", r.body_edge_crossings_after)
      .add("illegal_vertices", r.illegal_vertices)
      .add("impact_zones", r.impact_zones)
      .add("infeasible_zones", r.infeasible_zones)
      .add("body_closed", r.body_closed)
      .add("vertices_inside_before", r.vertices_inside_before)
      .add("vertices_inside_after", r.vertices_inside_after)
      .add("moved_vertices", r.moved_vertices)
      .add("clearance_m", r.clearance)
      .add("body_uncertainty_m", r.body_uncertainty)
      .add("near_vertices_pushed", r.near_vertices_pushed)
      .add("mean_displacement_m", r.mean_displacement)
      .add("max_displacement_m", r.max_displacement)
      .add("max_edge_strain", r.max_edge_strain)
      .add("p99_edge_strain", r.p99_edge_strain)
      .add("objective", r.objective)
      .add("relaxed", r.relaxed)
      .json("relaxation", toJson(r.relaxation, r))
      .add("time_budget_spent", r.time_budget_spent)
      .add("max_condition_estimate", r.max_condition_estimate)
      .add("seconds_detection", r.seconds_detection)
      .add("seconds_solve", r.seconds_solve)
      .add("seconds_relaxation", r.seconds_relaxation)
      .add("seconds_total", r.seconds_total)
      .str();
}

namespace {

// Each pattern seam's two stretch lengths and its take-in, metres: [{"a_m": .., "b_m": .., "take_in_m": ..}, ..].
std::string seamLengthsJson(const std::vector<DrapeResult::SeamLength>& seams) {
  std::string a = "[";
  for (std::size_t i = 0; i < seams.size(); ++i)
    a += (i ? ", " : "") +
         json::Obj().add("a_m", seams[i].a).add("b_m", seams[i].b).add("take_in_m", seams[i].take_in).str();
  return a + "]";
}

}  // namespace

std::string toJson(const DrapeResult& r) {
  return Obj()
      .add("success", r.success)
      .add("converged", r.converged)
      .add("cancelled", r.cancelled)
      .add("message", r.message)
      .add("warnings", r.warnings)
      .add("vertices", r.vertices)
      .add("triangles", r.triangles)
      .add("iterations", r.iterations)
      .add("sew_iterations", r.sew_iterations)
      .add("dt_s", r.dt)
      .add("dt_bound_s", r.dt_bound)
      .add("dt_bound_paper_s", r.dt_bound_paper)
      .add("map_size", r.map_size)
      .add("seconds_setup", r.seconds_setup)
      .add("seconds_simulation", r.seconds_simulation)
      .add("seconds_per_iteration", r.seconds_per_iteration)
      .add("seconds_resolve", r.seconds_resolve)
      .add("seconds_total", r.seconds_total)
      .add("seams_total", r.seams_total)
      .add("seams_open", r.seams_open)
      .add("seam_gap_max_m", r.seam_gap_max)
      .add("seam_gap_mean_m", r.seam_gap_mean)
      .add("strain_max", r.strain_max)
      .add("strain_mean", r.strain_mean)
      .add("strain_max_final", r.strain_max_final)
      .add("boundary_loops", r.boundary_loops)
      .add("openings", r.openings)
      .json("seams", seamLengthsJson(r.seam_lengths))
      .add("seam_take_in_max_m", r.seam_take_in_max)
      .add("max_speed_m_per_s", r.max_speed)
      .add("kinetic_energy_j", r.kinetic_energy)
      .add("penetrating_before_resolve", r.penetrating_before_resolve)
      .add("penetrating_after", r.penetrating_after)
      .add("resolver_run", r.resolver_run)
      .json("resolver", r.resolver_run ? toJson(r.resolver) : std::string("null"))
      .str();
}

}  // namespace virtual_tryon
