// From a raw body scan (points, optionally normals) to a closed, outward body mesh, through PCL:
//   0. the scanner's noise, estimated from the raw points (estimateScanNoise, scan_error.h);
//   1. drop non-finite points (counted);
//   2. optional voxel-grid downsampling (pcl::VoxelGrid: one point per occupied voxel, the mean);
//   3. normals: estimated when none are given (PCA of the k nearest neighbours), then oriented
//      outward by propagation over the symmetric kNN graph (Hoppe et al. 1992): a minimum spanning
//      tree with edge weights 1 - |ni . nj|, grown by Prim from a seed in every connected component
//      of the graph; the seed is the point farthest from the centre of its component's bounding box,
//      where the outward normal is the direction away from that centre. Given normals are used as
//      they are, unless more than `max_normal_disagreement` of the kNN graph's edges join normals
//      pointing opposite ways (dot < 0): then they are re-oriented by the same propagation;
//   4. pcl::Poisson surface reconstruction (Kazhdan et al. 2006, no trimming: the indicator's level
//      set is closed), at the depth chosen from the scan's extent, spacing and noise
//      (chooseScanDepth) unless one is given;
//   5. cleaning: unused vertices removed; cavities removed (`remove_cavities`: pieces wound opposite
//      to the largest piece, i.e. inner walls of air pockets in the indicator function, such as a
//      pocket closed off between touching thighs); optionally small pieces dropped
//      (`min_piece_fraction`);
//      small holes closed (`max_hole_edges`: PoissonRecon's adaptive octree occasionally leaves a
//      crack of a few edges between cells of different depths);
//   6. checkBody / orientBody: inverted pieces are flipped; success needs a closed mesh (0 boundary,
//      0 non-manifold edges) with positive volume;
//   7. the scan's error: the distance from the input points to the final mesh (measureScanError),
//      the error bar of the reconstruction, needing no ground truth. A fit to this body should
//      clear it by at least error.p95 (ResolverParams::body_uncertainty).
#pragma once

#include "virtual_tryon/core/body/body_check.h"
#include "virtual_tryon/core/body/scan_error.h"
#include "virtual_tryon/core/geometry/mesh.h"

#include <cstddef>
#include <string>

namespace virtual_tryon {

struct ScanMeshingParams {
  // Defaults: a 200k-point body scan meshes in about 4 s on a shared 2-core machine (depth 8 chosen:
  // cells of ~7.5 mm on a 1.7 m body; the points' 95th-percentile distance to the mesh is 1.1-1.2x
  // what the noise alone gives).
  double voxel_size = 0.005;   // metres, edge of the downsampling voxels; 0 = no downsampling (>= 0)
  int normal_neighbours = 16;  // k of the kNN normal estimation and orientation graph, 3 .. 100
  double max_normal_disagreement = 0.01;  // given normals: re-orient them when more than this
                                          // fraction of kNN edges disagree, 0 .. 1
  // Poisson octree depth: 0 = chosen from the scan (see chooseScanDepth), else 4 .. 12. The finest
  // cells are 1.1 x (largest bounding-box side) / 2^depth.
  int depth = 0;
  int max_auto_depth = 8;      // the deepest that depth 0 may choose, 4 .. 12 (time grows ~3x per level)
  double samples_per_node = 1.5;  // Poisson: minimum points per octree node (more = smoother), 1 .. 50
  double point_weight = 4.0;   // Poisson: weight of the interpolation constraint (>= 0)
  int threads = 0;             // Poisson solver threads (>= 0; 0 = one per core)
  bool remove_cavities = true;       // drop pieces wound opposite to the largest one (see 5.)
  double min_piece_fraction = 0.01;  // drop reconstructed pieces with fewer faces than this
                                     // fraction of the largest one; 0 keeps all, 0 .. 1
  int max_hole_edges = 64;           // close boundary loops of up to this many edges (a triangle
                                     // or a fan round their centroid); 0 = never, >= 0
  std::size_t min_points = 100;      // fewer valid points than this: refused (>= normal_neighbours + 1)
  std::size_t error_points = 50000;  // the scan's error is measured over at most this many input
                                     // points (an even stride; 0 = all)
};

// What meshScan did. Counts, booleans and seconds describe the run; `mesh` is the result.
struct ScanMeshingResult {
  bool success = false;
  std::string message;  // on failure: what went wrong (naming the parameter when one is invalid);
                        // on success: the body check's one-line summary
  TriMesh mesh;         // #V by 3, #F by 3: closed and outward on success (may be partial or empty
                        // on failure)

  std::size_t input_points = 0;        // #P given
  std::size_t non_finite_points = 0;   // dropped: NaN/Inf coordinates or, with normals, NaN/Inf/zero normal
  std::size_t points_after_downsampling = 0;  // points fed to the normal stage and Poisson
  bool normals_estimated = false;      // no normals given: estimated from the neighbours
  bool normals_reoriented = false;     // normals oriented by propagation (estimated, or given but
                                       // inconsistent)
  double normal_disagreement = 0;      // fraction of kNN edges with ni . nj < 0 before orienting
                                       // (given normals only; 0 when not measured)
  std::size_t normals_flipped = 0;     // normals whose sign the propagation changed
  std::size_t graph_components = 0;    // connected components of the kNN graph (orientation seeds;
                                       // 0 when the normals were not re-oriented)
  ScanNoiseEstimate noise;             // the scanner's noise, from the input points (scan_error.h)
  double point_spacing = 0;            // metres, median distance from a point fed to Poisson to its
                                       // nearest neighbour
  int depth = 0;                       // Poisson depth used (chosen when params.depth is 0)
  std::size_t poisson_vertices = 0, poisson_faces = 0;  // raw Poisson output
  std::size_t cavities_removed = 0;    // inner cavity walls removed (remove_cavities)
  std::size_t dropped_pieces = 0;      // small pieces removed (min_piece_fraction)
  std::size_t holes_filled = 0;        // boundary loops closed (max_hole_edges)
  std::size_t hole_faces_added = 0;    // faces added to close them
  std::size_t vertices = 0, faces = 0; // final mesh
  bool closed = false;
  std::size_t boundary_edges = 0, non_manifold_edges = 0;
  double signed_volume = 0;            // m^3, of the final mesh
  bool flipped = false;                // the reconstruction came out inverted and was flipped
  BodyCheck check;                     // the final body check (after flipping)
  ScanError error;                     // distance from the input points to the final mesh
  double error_ratio = 0;              // error.p95 / (1.96 noise.sigma): 1 when the mesh lies on
                                       // the true surface, larger when it smooths details away
                                       // (0 when no noise was measured)

  double seconds_noise = 0;            // the noise estimate
  double seconds_downsample = 0;       // filtering non-finite points and the voxel grid
  double seconds_normals = 0;          // kNN search and normal estimation (or the consistency test)
                                       // (all seconds are wall-clock)
  double seconds_orient = 0;           // the symmetric kNN graph and the orientation propagation
  double seconds_reconstruct = 0;      // pcl::Poisson
  double seconds_cleanup = 0;          // conversion, unused vertices, cavities, small pieces, holes,
                                       // body check
  double seconds_error = 0;            // the error measurement
  double seconds_total = 0;
};

// Meshes a scan. `points` is #P by 3 (metres); `normals` is #P by 3 (any length > 0, outward or
// not) or empty (0 rows) to estimate them. Never throws: errors are reported in the result.
ScanMeshingResult meshScan(const MatrixX3d& points, const MatrixX3d& normals,
                           const ScanMeshingParams& params = ScanMeshingParams());

// Closes the boundary loops (holes) of `mesh` (#V by 3, #F by 3, consistently wound) that have at
// most `max_hole_edges` edges: a 3-edge loop with one triangle, a longer one with a fan round a new
// vertex at its centroid (appended to V), wound to match the faces around the loop. A loop that
// passes a vertex twice is split there; a boundary that dead-ends (non-manifold) is left open.
// Returns the number of loops closed; `faces_added` (optional) receives the faces appended to F.
std::size_t closeSmallHoles(TriMesh& mesh, int max_hole_edges, std::size_t* faces_added = nullptr);

// The Poisson depth for a scan whose largest bounding-box side is `extent` (m), whose points lie
// `spacing` apart (m, median nearest-neighbour distance) with noise `sigma` (m): the coarsest depth
// whose finest cell, 1.1 extent / 2^depth, is at most max(1.5 spacing, 2 sigma), within
// [5, max_depth]. Finer cells than the points' spacing add no detail (Poisson needs several points
// per cell) and cost ~3x per level; coarser ones smooth away the limbs' curvature.
int chooseScanDepth(double extent, double spacing, double sigma, int max_depth);

// Checks the parameters; returns "" when valid, else a message naming the first bad parameter and
// its allowed range.
std::string validateScanMeshingParams(const ScanMeshingParams& params);

}  // namespace virtual_tryon
