// Sun, Nyberg, Xiong, Ye (2016), "Minimum displacements for cloth-obstacle penetration
// resolving": history-free, orientation-based separation of a garment from a rigid body.
//
// Each round: detect every edge-face crossing in both directions (intersections.h), turn each into
// a stencil (stencils.h), group stencils that share garment vertices into impact zones and solve
// each zone for the minimum displacement (impact_zones.h), move the garment. Repeat until no
// crossing is left, or the iteration limit, or no progress (the paper's Fig. 5 cases).
#pragma once

#include "virtual_tryon/core/body/body.h"
#include "virtual_tryon/core/geometry/mesh.h"
#include "virtual_tryon/core/resolve/shape_relaxation.h"

#include <cstddef>
#include <functional>
#include <memory>
#include <string>
#include <vector>

namespace virtual_tryon {

// How each round turns the stencils into displacements.
enum class ZoneSolver {
  // The paper: stencils that share garment vertices form an impact zone, solved together for the
  // minimum displacement (eq. 7, lambda >= 0; impact_zones.h). The default.
  ImpactZone,
  // A baseline for the evaluation, not a method of the paper: every stencil is projected on its
  // own (lambda_i = max(0, (d - D_i) / |grad_i|^2)), and a vertex several stencils move gets the
  // mean of their displacements (Jacobi projection with constraint averaging). No zones, so no
  // contradiction is ever detected: such spots only stall.
  PerStencilProjection,
};

// What a converged run does with the garment's shape.
enum class ResolverObjective {
  // The paper as written: the rounds' minimum displacements and nothing else. Each illegal vertex
  // is lifted to the plane of the crossed body face (eq. 1), which on a curved body lies above the
  // surface under it, and only stencil vertices move, so single vertices stand out as spikes.
  Paper,
  // The default: the paper's rounds, then the shape relaxation of shape_relaxation.h (moved
  // vertices and their rings share the move, edges keep their input vectors as far as the body
  // allows, no crossing comes back).
  Smooth,
};

// One entry per step of the run, for error-against-time plots: the state after the first
// detection (iteration 0), then after every round (and after a push-out of wholly inside pieces).
struct ResolverIteration {
  int iteration = 0;       // rounds done so far
  double seconds = 0;      // since the call began, without the time spent in on_iteration
  std::size_t garment_edge_crossings = 0;  // by the resolver's own detector, after this step
  std::size_t body_edge_crossings = 0;
  std::size_t vertices_inside = 0;   // closed body: garment vertices inside, as the resolver tracks them
  std::size_t illegal_vertices = 0;  // found behind a body face in this round
  std::size_t stencils = 0;
  std::size_t impact_zones = 0;      // 0 for ZoneSolver::PerStencilProjection
  std::size_t infeasible_zones = 0;
  std::size_t moved_vertices = 0;    // moved in this step
  double max_condition_estimate = 1;  // largest pivot ratio of this round's direct zone solves
  bool push_out = false;  // this step pushed garment pieces found wholly inside to the surface
};

// A garment's edge lists and neighbour graph, which its faces alone decide: every call builds its
// own unless it is handed one. The frames of one garment (the same faces, new positions) build it
// once and hand it to each frame's calls (ResolverParams::connectivity,
// CoherenceParams::connectivity).
struct GarmentConnectivity;
std::shared_ptr<const GarmentConnectivity> garmentConnectivity(const TriMesh& garment);

struct ResolverParams {
  // Clearance d of eq. 7 in metres; <= 0 means clearance_fraction * mean garment edge length.
  double clearance = 0.0;
  double clearance_fraction = 0.05;
  // How far the true surface may lie outside the body mesh, metres (>= 0; 0: the mesh is the
  // surface). For a body meshed from a scan, the scan's error (ScanError::p95). When > 0 the
  // clearance used is d + body_uncertainty, and before the rounds every garment vertex inside the
  // body or nearer to it than that clearance is moved to its nearest body point plus the clearance
  // (the smooth objective's relaxation then keeps every vertex at least that far out).
  double body_uncertainty = 0.0;
  int max_iterations = 100;
  // Stop as not converged when the error (crossings plus garment vertices inside the body) has not
  // reached a new minimum for this many rounds (a configuration that orientation alone cannot
  // resolve, the paper's Fig. 5).
  int stall_iterations = 12;
  // For a closed body, test whether garment pieces with no crossing edge lie wholly inside.
  bool check_inside = true;
  // Move garment pieces found wholly inside out to the nearest body point (+ clearance) and go on
  // resolving; when false they are only reported.
  bool push_out_inside = true;
  ZoneSolver solver = ZoneSolver::ImpactZone;
  ResolverObjective objective = ResolverObjective::Smooth;
  ShapeRelaxationParams relaxation;  // for ResolverObjective::Smooth
  // A warm start (resolvePenetrationsFrom, a start other than the input itself): the relaxation
  // runs locally (ShapeRelaxationParams::local, seeded with the vertices the rounds moved), and
  // once more over every vertex away from its input when the local result leaves an edge strained
  // past warm_full_relaxation_strain against the input. false: always over every moved vertex.
  bool warm_local_relaxation = true;
  double warm_full_relaxation_strain = 0.25;
  // Smooth objective: before the rounds, move every vertex found inside to its nearest body point
  // plus the clearance (a closed body, and push_out_inside), so the rounds only clear what a
  // vertex cannot see. A time budget also bounds the relaxation (what is left of it).
  bool push_out_first = true;
  // Wall-clock limit in seconds (0: none), checked before every round. When spent the run stops,
  // not converged, the reason says so, and the garment is left in the best state reached.
  double time_budget = 0;
  // Optional observer, called with every trace entry and the garment as it is then (e.g. to count
  // crossings independently). Its time is left out of every time the resolver reports.
  std::function<void(const ResolverIteration&, const TriMesh& garment)> on_iteration;
  // The garment's connectivity (garmentConnectivity of a mesh with its faces), when the caller has
  // it; else, or when its vertex or face count is not the garment's, the call builds its own.
  std::shared_ptr<const GarmentConnectivity> connectivity;
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
  bool time_budget_spent = false;
  double max_condition_estimate = 1;  // over every direct zone solve of the run (ZoneSolution)
  std::size_t moved_vertices = 0;
  double clearance = 0;           // m, used: d (+ body_uncertainty)
  double body_uncertainty = 0;    // m, as given
  std::size_t near_vertices_pushed = 0;  // body_uncertainty > 0: vertices moved out before the rounds
  double mean_displacement = 0;  // over moved vertices
  double max_displacement = 0;
  // Shape against the input garment, over its edges of non-zero length: the largest and the
  // 99th-percentile (nearest rank) edge strain |l / l0 - 1|.
  double max_edge_strain = 0;
  double p99_edge_strain = 0;
  std::string objective;          // "paper" or "smooth"
  bool relaxed = false;           // the shape relaxation ran (smooth objective, converged)
  double max_edge_strain_before_relaxation = 0;  // the rounds' own result, when relaxed
  // A warm start's local relaxation left an edge past warm_full_relaxation_strain (this strain, its
  // largest), and the relaxation ran again over every moved vertex; `relaxation` is that run's.
  bool relaxation_widened = false;
  double max_edge_strain_after_local_relaxation = 0;
  ShapeRelaxationReport relaxation;
  double seconds_detection = 0;
  double seconds_solve = 0;
  double seconds_relaxation = 0;
  double seconds_total = 0;
  std::vector<ResolverIteration> trace;  // see ResolverIteration
};

// Resolves `garment` (#V by 3 positions change, faces and vertex order do not) against `body`.
// The garment must be valid (see validate()); the body must be valid and outward-oriented (a
// closed body with negative volume, i.e. inside out, is refused: not converged, nothing moved).
//
// When the run stops without converging (iteration limit, no progress, time budget), the garment
// is left in the state with the smallest error (crossings plus vertices inside, by the resolver's
// own detector) reached since the last push-out (the earliest of equals), and the "after" counts
// describe that state.
//
// Cost: one full detection pass (and, for a closed body, one ray test per connected garment
// piece); after that every round touches only the stencils, the moved vertices and the faces
// round them, so a frame with few penetrating vertices costs little beyond the first pass.
ResolverReport resolvePenetrations(const Body& body, TriMesh& garment,
                                   const ResolverParams& params = ResolverParams());

// A warm start, for the frames of an animation: `garment` comes in at a start of the caller's
// choosing (say, this frame's input moved by the previous frame's correction) and is resolved from
// there as a whole, exactly as above, so the result is correct on its own whatever the start. The
// garment's own `input` (same faces and vertex order; else refused, nothing moved) is what the
// shape relaxation keeps the shape of and pulls back to, and what the report's strain and
// displacement are measured against: a correction the start carries but this input no longer
// needs is given back, and one that the input's motion would strain is turned with it. The
// relaxation runs even when the start is already clean (locally, with warm_local_relaxation: round
// what the rounds moved and the edges the start strains). The "before" counts are the start's.
ResolverReport resolvePenetrationsFrom(const Body& body, const TriMesh& input, TriMesh& garment,
                                       const ResolverParams& params = ResolverParams());

// m: the smallest correction that warmStart() carries over with the full relaxation
// (warm_local_relaxation false). The smaller ones are mostly what that relaxation spread round a
// push; carried over, they would be spread a few rings further every frame, until the whole
// garment floats off its input (on the walk's skirt: 161 vertices that started over 1 cm from the
// body moved by frame 30, against 39 cold; 5 with 2 mm). The local relaxation does not spread
// them, and a cut at 2 mm would leave the edges between carried and dropped corrections strained
// (the skirt's p99 0.015 -> 0.047), so with it every correction is carried (0).
constexpr double kWarmStartMinCorrection = 0.002;

// The smallest correction carried over by default for these parameters: 0 with
// warm_local_relaxation, else kWarmStartMinCorrection.
double defaultWarmStartMin(const ResolverParams& params);

// The warm start of an animation frame: `input` (#V by 3) moved by the previous frame's
// `correction` (resolved minus input, #V by 3) on the vertices where that correction is at least
// `minCarried` metres (see kWarmStartMinCorrection). Sizes that do not match: `input`.
MatrixX3d warmStart(const MatrixX3d& input, const MatrixX3d& correction, double minCarried = kWarmStartMinCorrection);

// How resolveFrame() started a frame.
enum class FrameStart { Cold, Warm, WarmFailedResolvedCold };

// What an animation frame leaves for the next one: its input and its correction (resolved minus
// input), each #V by 3 in the garment's vertex order. An empty correction: no frame before.
struct PreviousFrame {
  MatrixX3d input;
  MatrixX3d correction;
};

// One frame of an animation: `garment` comes in as the frame's input and leaves resolved. With a
// previous.correction of its size, it starts from warmStart(input, previous.correction, minCarried)
// (resolvePenetrationsFrom; minCarried < 0: defaultWarmStartMin(params)), its local relaxation
// seeded against the frame before when previous.input has that size too; a warm start that does not converge is resolved again from the input
// alone, its time added, so the frame is correct on its own whatever the frame before did. Else
// (empty correction, say) resolvePenetrations. `start` (may be null) says which it was.
ResolverReport resolveFrame(const Body& body, TriMesh& garment, const PreviousFrame& previous,
                            const ResolverParams& params = ResolverParams(), double minCarried = -1,
                            FrameStart* start = nullptr);

}  // namespace virtual_tryon
