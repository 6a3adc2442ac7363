// Shape relaxation after the resolver: the garment gives back what the resolve did not need.
//
// Sun et al.'s rounds move the vertices of each stencil and nothing else, by the depth below the
// crossed body face's plane. On a curved body that plane lies above the surface under the illegal
// vertex, and a body face is much smaller than a garment edge, so single vertices are lifted far
// past the surface (spikes, tents) while their neighbours stay. This stage starts from the
// resolver's clean state and minimises, over the moved vertices and a few rings round them,
//   E(x) = sum over edges (i, j) of |(x_i - x_j) - (R_i + R_j) / 2 (x0_i - x0_j)|^2
//          + mu sum over i of |x_i - x0_i|^2,
// the change of every edge vector against its input vector x0_i - x0_j turned by the local
// rotations R_i of its ends (as-rigid-as-possible, Sorkine and Alexa 2007: the garment may bend
// round the body, only stretch and shear cost; each R_i is refitted to its one-ring every check,
// warm-started, by the iteration of Mueller et al. 2016; with local_rotations off R = I and E is
// the change of the edge vectors themselves), plus a small pull back to the input, subject to:
//   - every vertex stays outside the body by its floor: the clearance d for a vertex that the
//     resolver moved, the smaller of d and its input distance for the others (a vertex that sat
//     closer than d is not pushed); the body is seen through the tangent plane at each vertex's
//     nearest body point, refreshed when the vertex has moved `replane_distance` from where it was
//     taken;
//   - no new edge-face crossing in either direction: every `sweeps_per_check` sweeps the faces
//     round the vertices that moved are detected again. Each new crossing becomes a contact that
//     every later sweep keeps (a body edge through a garment face: that face's point must pass the
//     edge's outer end by d along the edge's normal; a garment edge through a body face: the
//     edge's point must pass the face's plane by d), projected by moving its corners together
//     along its normal. The vertices of a new crossing also step back half way to their last
//     clean position (up to `bisections` times, then all the way, then, should the crossing
//     remain, to the resolver's state; each vertex by its own level, only the vertices of
//     crossings) and rest for `hold_sweeps`
//     sweeps while their neighbours relax round them.
// Projected Gauss-Seidel: each vertex in turn goes to where its neighbours put it, then onto its
// half-space; then the strain limit and the contacts. The garment is clean after every check, so
// the stage can stop anywhere (sweep limit, step below `tolerance`, time budget) and keep what it
// has. Last, a polish: a step back leaves single edges torn between a vertex that stepped back and
// one that did not, so edges strained beyond `polish_strain` are brought back to it (the contacts
// and half-spaces kept, each pass checked like a sweep), and again after the final check if that
// stepped anything back; a first polish round at `fine_polish_strain` brings the many edges
// between the two limits down too.
#pragma once

#include "virtual_tryon/core/body/body.h"
#include "virtual_tryon/core/geometry/mesh.h"
#include "virtual_tryon/core/resolve/intersections.h"

#include <cstddef>
#include <vector>

namespace virtual_tryon {

// One edge's rest length: garment vertices a and b, metres.
struct EdgeRestLength {
  int a = -1, b = -1;
  double rest = 0;
};

struct ShapeRelaxationParams {
  int max_sweeps = 18;
  int sweeps_per_check = 3;        // crossings are checked after every this many sweeps (and at the end)
  double over_relaxation = 1.8;   // successive over-relaxation factor of the sweeps (1: Gauss-Seidel)
  double mu = 0.005;              // pull back to the input, against a neighbour's weight of 1
  int rings = 8;                  // rings of unmoved neighbours that may move too
  double replane_distance = 0.002;  // m: refresh a vertex's body plane after this move
  double tolerance = 1e-5;        // m: stop when no vertex moved more than this in a sweep
  int bisections = 2;
  // m: a sweep checks the faces round the vertices that moved more than this since they were last
  // checked; at the end every moved vertex is checked, so the result is clean whatever this is.
  double check_distance = 0.0005;
  // After each sweep, edges strained past this (|l / l0 - 1|) are brought back to it (position-
  // based, both ends sharing the correction); 0: off.
  double strain_limit = 0.1;
  // Compare each edge with its input vector turned by its ends' local rotations (as-rigid-as-
  // possible), so that the garment may bend round the body and only stretch costs; false: with the
  // input vector as it is.
  bool local_rotations = true;
  int hold_sweeps = 6;            // a vertex that stepped back rests for this many sweeps
  // m; when > 0, with every crossing check: each body vertex under a checked garment face nearer to
  // it than this (along the vertex's normal) becomes a contact that keeps the face's point there
  // this far out. The vertex floors keep a face's corners out; this keeps the middle of a large
  // face out where the body bulges under it. The resolver sets it to its clearance when the body
  // has an uncertainty (a scan), so that the whole garment surface clears the mesh by d + u; it
  // also lifts, before the rounds, every face whose middle passes nearer than that (0: that
  // default; < 0: off, in both places).
  double face_clearance = 0;
  // After the sweeps, this many passes bring every edge strained beyond polish_strain back to it
  // (vertices that stepped back too), each checked like a sweep; 0: none (one pass still projects
  // the contacts found by the last check).
  int polish_passes = 5;
  double polish_strain = 0.2;
  // When in (0, polish_strain): the first polish round brings edges back to this instead, and the
  // rounds at polish_strain always follow it (an edge that must stretch, a hem round an arm, is
  // torn again by a step back there, and the coarse rounds mend that). On body_hm08 it takes the
  // female jeans' 99th-percentile strain from 0.117 to 0.103 and the female T-shirt's from 0.155
  // to 0.129. Other values (0, or not below polish_strain): one limit, polish_strain.
  double fine_polish_strain = 0.1;
  double time_budget = 0;         // s, 0: none
  // A sewn garment's rest lengths (its structural springs in the flat pattern). With rest_strain
  // > 0 both strain limits (the sweeps' and the polish's) also keep each listed edge within
  // (1 + rest_strain) of its rest length, or at its input length where the input was already
  // longer: the resolver does not stretch a draped garment's springs past what the drape allows.
  // Edges not in the list, and pairs that are not edges, are left as without it.
  std::vector<EdgeRestLength> rest_lengths;
  double rest_strain = 0;
  // Local relaxation (a warm start of an animation frame, which carries the frame before's
  // corrections, so that nearly every vertex is away from its input although only a few crossings
  // came in): when set, the stage starts only from `seeds` (vertex indices; the resolver passes the
  // vertices its rounds moved) and from both ends of every edge strained past local_seed_strain
  // (|l / l0 - 1|) against the input, then local_rings rings round them, instead of every vertex
  // away from its input and `rings` rings. Every other vertex keeps its position. Given the frame
  // before's input and result (#V by 3 each, the garment's vertex order; else empty), an edge is
  // seeded only where it is also strained more than that result strained it, by local_seed_growth:
  // an edge the frame before's relaxation left strained, and that the motion did not strain
  // further, is left as it is (on the walk's jeans, 436 -> 111 relaxed vertices a frame).
  bool local = false;
  std::vector<int> seeds;
  double local_seed_strain = 0.1;
  int local_rings = 3;
  // The sweeps of a local relaxation (0: max_sweeps). It starts from the frame before's relaxed
  // shape, moved by the motion, and its few hundred vertices take a few sweeps: on the walk, 6
  // instead of 18 took the jeans' warm frame from 3.2 to 2.7 ms (female T-shirt 3.0 to 2.6) with
  // the largest strain and the p99 within 0.01 of 18's and every frame clean.
  int local_max_sweeps = 6;
  MatrixX3d local_previous_input, local_previous_result;
  double local_seed_growth = 0.01;
};

struct ShapeRelaxationReport {
  std::size_t active_vertices = 0;   // vertices the stage may move
  bool local = false;                // chosen round the seeds (ShapeRelaxationParams::local)
  int sweeps = 0;
  std::size_t steps_back = 0;        // vertex steps undone (halved or reverted) to stay clean
  std::size_t plane_queries = 0;     // nearest-body-point queries
  std::size_t detections = 0;        // crossing detections over the moved faces
  std::size_t faces_checked = 0;     // garment faces over all detections
  std::size_t candidates_reused = 0; // of those, answered from their kept candidates (no tree query)
  double seconds_checks = 0;         // of `seconds`, in the crossing checks (detections, steps back)
  double seconds_setup = 0;          // of `seconds`, choosing the active vertices and their body planes
  double seconds_rotations = 0;      // of `seconds`, fitting the local rotations
  std::size_t contacts = 0;          // crossings found by the checks and kept as contacts
  double last_step = 0;              // m, largest vertex move of the last sweep
  bool clean = true;                 // no crossing was left (always, unless detection failed)
  double seconds = 0;
};

// `input` (the garment before the resolver) and `garment` (its clean resolved state) share faces
// and vertex order; `topo` is the garment's GarmentTopology. `clearance` is the resolver's d (m).
// Only vertices of `garment` change.
ShapeRelaxationReport relaxShape(const Body& body, const TriMesh& input, TriMesh& garment,
                                 const GarmentTopology& topo, double clearance,
                                 const ShapeRelaxationParams& params = ShapeRelaxationParams());

}  // namespace virtual_tryon
