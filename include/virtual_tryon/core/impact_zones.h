// Impact zones and the minimum-displacement solve (Sun et al. 2016, eqs. 2-7).
//
// Stencils that share a garment vertex form one impact zone. For a zone with k stencils and
// gradient matrix Dx (3n by k, column i = stencil i's gradient), the displacement is
//   dx = Dx lambda,  (Dx^T Dx) lambda = -D + d                                   (eq. 7)
// Beyond the paper, lambda is kept non-negative (a stencil may only push its vertices out, never
// pull them in): an active-set loop drops stencils whose lambda would go negative and re-adds
// those the others leave violated, so the result is the minimum-norm displacement with
// D + Dx^T dx >= d. Zones of more than 64 stencils are solved instead by Hildreth's method (the same
// problem, projected Gauss-Seidel on lambda >= 0, to a tolerance of 1e-4 d). A tiny Tikhonov term keeps duplicate or parallel stencils solvable; a zone whose
// constraints still cannot all be met (opposing normals, the paper's Fig. 5) is marked infeasible.
#pragma once

#include "virtual_tryon/core/stencils.h"

#include <vector>

namespace virtual_tryon {

// Groups stencils that share garment vertices. Returns the zones as lists of stencil indices
// (each list sorted; zones ordered by their first stencil). `numVertices` is the garment's #V.
std::vector<std::vector<int>> groupImpactZones(const std::vector<Stencil>& stencils, int numVertices);

struct ZoneSolution {
  std::vector<int> vertices;             // garment vertices the zone moves
  std::vector<Eigen::Vector3d> displacement;  // one per entry of `vertices`
  std::vector<double> lambda;            // one per stencil of the zone, all >= 0
  bool feasible = true;                  // every constraint met within tolerance
  double max_violation = 0;              // max(d - D - grad . dx, 0) after the solve, metres
  double condition_estimate = 1;         // max/min pivot of the LDL^T factorization
  int active_set_rounds = 0;            // exact solves of the active set (small zones)
  int sweeps = 0;                       // Hildreth sweeps (large zones, or a cycling active set)
};

// Solves one zone for clearance d (metres).
ZoneSolution solveImpactZone(const std::vector<Stencil>& stencils, const std::vector<int>& zone,
                             double d);

}  // namespace virtual_tryon
