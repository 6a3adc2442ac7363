// Sun, Nyberg, Xiong, Ye (2016), "Minimum displacements for cloth-obstacle penetration
// resolving": history-free, orientation-based separation of a garment from a rigid body.
//
// Each round: detect every edge-face crossing in both directions (intersections.h), turn each into
// a stencil (stencils.h), group stencils that share garment vertices into impact zones and solve
// each zone for the minimum displacement (impact_zones.h), move the garment. Repeat until no
// crossing is left, or the iteration limit, or no progress (the paper's Fig. 5 cases).
#pragma once

#include "virtual_tryon/core/body.h"
#include "virtual_tryon/core/mesh.h"

#include <cstddef>
#include <string>

namespace virtual_tryon {

struct ResolverParams {
  // Clearance d of eq. 7 in metres; <= 0 means clearance_fraction * mean garment edge length.
  double clearance = 0.0;
  double clearance_fraction = 0.05;
  int max_iterations = 100;
  // Stop as not converged when the number of crossings has not reached a new minimum for this many
  // rounds (a configuration that orientation alone cannot resolve, the paper's Fig. 5).
  int stall_iterations = 12;
  // For a closed body, test whether garment pieces with no crossing edge lie wholly inside.
  bool check_inside = true;
  // Move garment pieces found wholly inside out to the nearest body point (+ clearance) and go on
  // resolving; when false they are only reported.
  bool push_out_inside = true;
};

struct ResolverReport {
  bool converged = false;
  std::string reason;
  int iterations = 0;
  std::size_t garment_edge_crossings_before = 0;
  std::size_t body_edge_crossings_before = 0;
  std::size_t garment_edge_crossings_after = 0;
  std::size_t body_edge_crossings_after = 0;
  std::size_t illegal_vertices = 0;  // distinct garment vertices found illegal over the run
  std::size_t impact_zones = 0;      // summed over rounds
  std::size_t infeasible_zones = 0;  // summed over rounds
  std::size_t vertices_inside_before = 0;
  std::size_t vertices_inside_after = 0;
  bool body_closed = false;
  std::size_t moved_vertices = 0;
  double clearance = 0;
  double mean_displacement = 0;  // over moved vertices
  double max_displacement = 0;
  double seconds_detection = 0;
  double seconds_solve = 0;
  double seconds_total = 0;
};

// Resolves `garment` (#V by 3 positions change, faces and vertex order do not) against `body`.
// The garment must be valid (see validate()); the body must be valid and outward-oriented.
ResolverReport resolvePenetrations(const Body& body, TriMesh& garment,
                                   const ResolverParams& params = ResolverParams());

}  // namespace virtual_tryon
