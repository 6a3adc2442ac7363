// Vassilev, Spanlang, Chrysanthou (2001), "Fast cloth animation on walking avatars" / dressing
// virtual humans: the garment's patterns are meshed into grids, placed round the body, sewn by
// seam forces, welded when the seams close, draped until the cloth settles, with image-space (or
// object-space) collisions; then the penetration resolver (Sun et al. 2016) cleans what the
// collisions let through.
#pragma once

#include "virtual_tryon/core/body/body.h"
#include "virtual_tryon/core/drape/cloth.h"
#include "virtual_tryon/core/drape/collider.h"
#include "virtual_tryon/core/drape/pattern.h"
#include "virtual_tryon/core/resolve/penetration_resolver.h"

#include <functional>
#include <optional>
#include <string>
#include <vector>

namespace virtual_tryon {

struct DrapeParams {
  double spacing = 0.02;  // grid spacing of the panels, metres (sets the vertex count)
  ClothParams cloth;
  CollisionParams collision;
  CollisionMode mode = CollisionMode::ImageSpace;
  bool quad_midpoints = true;  // also test each quad's midpoint (sec. 6)
  // Beyond the paper: a node found deeper than tol also moves out by this fraction of the excess
  // depth per step (0: the paper's velocity-only response).
  double push_out = 0.0;
  double dt = 0;               // seconds; 0: dt_safety * the eq. 4 bound
  double dt_safety = 0.9;
  bool clamp_dt = false;       // a dt above the bound: refuse (false) or clamp with a warning (true)
  double weld_tolerance = 0;   // metres; 0: half the spacing, at least 1.5 cm
  int max_sew_iterations = 4000;
  int max_iterations = 8000;   // sewing and draping together
  int min_drape_iterations = 40;
  // m/s: after welding, settled when the nodes' net speed over the last 0.1 s of simulated time
  // (at least 25 iterations), displacement / duration, rms over the nodes, is below it (the
  // instantaneous speed of a resting cloth is mostly contact chatter: see drape.cpp)
  double settle_speed = 0.02;
  double time_budget = 0;      // seconds of wall clock; 0: none. When spent: best state, not converged
  // The largest structural-spring strain |l / l0 - 1| of the returned garment (after the resolver)
  // a converged drape may have; above it the drape is not converged and says so. 0: no limit.
  double max_strain = 0.15;
  bool resolve = true;         // run the penetration resolver on the result
  // The final resolve's shape relaxation brings edges strained past this (against the draped
  // garment, its input) back to it, instead of resolver.relaxation.polish_strain: the draped cloth
  // already carries its own strain, and at 0.2 the resolve added up to 0.15 more to the sleeveless
  // shirt's straps (0.064 -> 0.218). 0: the resolver's own.
  double resolve_polish_strain = 0.05;
  // The final resolve also keeps every structural spring within (1 + this) of its rest length (or
  // at its draped length, if it was longer already): a spring at 0.12 as draped gained the 0.05
  // above and ended over max_strain (the procedural T-shirt at 3 cm: 0.123 -> 0.158). 0: off.
  double resolve_rest_strain = 0.14;
  ResolverParams resolver;
  MeshLimits limits;           // the cloth's node count (meshPattern) is held to limits.max_vertices
};

struct DrapeProgress {
  int iteration = 0;
  bool sewing = true;
  double seam_gap = 0;        // largest open seam gap, metres
  double kinetic_energy = 0;  // J
  double max_speed = 0;       // m/s
  double seconds = 0;
};
// Called every `progress_every` iterations; return false to cancel.
using DrapeProgressCallback = std::function<bool(const DrapeProgress&)>;

struct DrapeResult {
  bool success = false;    // false: bad input or the integration blew up (see message)
  bool converged = false;  // seams welded, watertight, cloth settled, and (if run) the resolver converged
  bool cancelled = false;
  std::string message;     // the error, or a one-line summary
  std::vector<std::string> warnings;
  std::size_t vertices = 0, triangles = 0;
  int iterations = 0, sew_iterations = 0;
  double dt = 0, dt_bound = 0;  // seconds; dt_bound: eq. 4 per node (ClothState::stableTimeStep)
  double dt_bound_paper = 0;    // eq. 4 with the stiffest single spring (reported only)
  int map_size = 0;             // image space: pixels along the longer side
  double seconds_setup = 0;     // meshing, and maps or BVH if not cached yet
  double seconds_simulation = 0;
  double seconds_per_iteration = 0;
  double seconds_resolve = 0;
  double seconds_total = 0;
  int seams_total = 0, seams_open = 0;
  double seam_gap_max = 0, seam_gap_mean = 0;  // of the seams still open, metres
  double strain_max = 0, strain_mean = 0;      // |l / l0 - 1| over structural springs, as draped
  // The largest of the same over the returned garment (after the resolver moved it): what
  // max_strain judges, the largest of vertex_strain.
  double strain_max_final = 0;
  // Boundary loops of the welded garment, and the openings its pattern has (the loops of unsewn
  // outline, patternOpenings()): a watertight garment has as many of the one as of the other, and
  // a converged drape must be watertight.
  std::size_t boundary_loops = 0, openings = 0;
  // Per pattern seam, in the pattern's order: the lengths of its two outline stretches (m, flat
  // pattern) and the length that the longer one takes in to be sewn to the shorter (their
  // difference: ease or gathers); and the largest take-in of all.
  struct SeamLength {
    double a = 0, b = 0, take_in = 0;
  };
  std::vector<SeamLength> seam_lengths;
  double seam_take_in_max = 0;
  double max_speed = 0, kinetic_energy = 0;    // at the end (instantaneous)
  double net_speed = 0;  // m/s: the last settle test's net rms speed over its window (0: none yet)
  // Garment vertices inside the body mesh (not the maps), before and after the resolver pass.
  std::size_t penetrating_before_resolve = 0, penetrating_after = 0;
  bool resolver_run = false;
  ResolverReport resolver;
  // #V by 3: the garment as draped, before the resolver pass moved it (empty when it did not run),
  // so that a viewer can show what the resolver moved.
  MatrixX3d draped_vertices;
  // #V of the garment: the largest |l / l0 - 1| of the structural springs at each vertex, for the
  // final garment (after the resolver): the fit map (render/fit_render.h, the rviz markers).
  std::vector<double> vertex_strain;
};

// Drapes `pattern` on `body`; the result (welded, one mesh) goes to `garment` even when not
// converged, as long as success is true.
DrapeResult drape(const Body& body, const Pattern& pattern, const DrapeParams& params,
                  TriMesh& garment, const DrapeProgressCallback& progress = nullptr,
                  int progress_every = 25);

// The same, also handing over the cloth that made `garment` (empty unless success): its nodes are
// garment's vertices, at garment's positions (after the resolver), with their velocities, springs
// and masses, and no collision hook; what a garment worn on a moving body steps on from
// (worn_garment.h).
DrapeResult drape(const Body& body, const Pattern& pattern, const DrapeParams& params, TriMesh& garment,
                  std::optional<ClothState>& cloth, const DrapeProgressCallback& progress = nullptr,
                  int progress_every = 25);

// Checks parameters; "" or a message naming the parameter and the allowed range. Mass (density),
// stiffnesses, damping, tol, map_size, friction, reflection, dt, iteration counts, settle speed,
// weld tolerance, time budget, and the limits (max_vertices, max_faces >= 1).
std::string validateDrapeParams(const DrapeParams& params);

}  // namespace virtual_tryon
