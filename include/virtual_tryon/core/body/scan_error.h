// How well a mesh made from a scan follows the scan, measured from the scan alone (no ground truth):
//   - the scanner's noise, estimated from the points: each sampled point against a quadric fitted
//     to its nearest neighbours (itself left out), in the neighbours' principal frame, the
//     residual along the quadric's normal divided by sqrt(1 + leverage) so that it has the noise's
//     own spread; sigma = median |residual| / 0.6745 (the normal distribution's median absolute
//     deviation), robust to the few points on edges and thin parts. The quadric takes the
//     surface's curvature out, which a plane fit would count as noise;
//   - the distance from the points to the mesh: median, 95th percentile, largest, and the share of
//     points farther than 2 mm. A mesh that lies on the true surface gives the noise's own
//     distances: |N(0, sigma)| has its 95th percentile at 1.96 sigma.
#pragma once

#include "virtual_tryon/core/geometry/mesh.h"

#include <cstddef>

namespace virtual_tryon {

struct ScanNoiseEstimate {
  double sigma = 0;          // metres, the estimated standard deviation of the noise along the
                             // surface normal (0 when too few points)
  std::size_t samples = 0;   // points whose residual was used
  double seconds = 0;
};

// `points` is #P by 3 (finite rows only are used). Samples at most `max_samples` points (evenly
// strided) and fits each to its `neighbours` nearest points (>= 10). Never throws.
ScanNoiseEstimate estimateScanNoise(const MatrixX3d& points, std::size_t max_samples = 4000,
                                    int neighbours = 20);

struct ScanError {
  std::size_t points = 0;     // points measured (all finite points, or an even stride of them)
  double median = 0;          // metres, distance from a point to the mesh
  double p95 = 0;             // 95th percentile (nearest rank)
  double max = 0;             // largest over the points measured
  double share_over_2mm = 0;  // fraction of the points measured farther than 0.002 m
  double seconds = 0;
};

// Distance from the finite rows of `points` (#P by 3) to `mesh` (#V by 3, #F by 3, non-empty), at
// most `max_points` of them (an even stride; 0 = all). Never throws; an empty mesh gives zeros.
ScanError measureScanError(const MatrixX3d& points, const TriMesh& mesh, std::size_t max_points = 50000);

}  // namespace virtual_tryon
