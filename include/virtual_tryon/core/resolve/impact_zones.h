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

#include "virtual_tryon/core/resolve/stencils.h"

#include <vector>

namespace virtual_tryon {

// Groups stencils that share garment vertices. Returns the zones as lists of stencil indices
// (each list sorted; zones ordered by their first stencil). `numVertices` is the garment's #V.
// Cost O(s log s) in the number of stencils s, whatever numVertices.
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

// The baseline of ZoneSolver::PerStencilProjection (not the paper's method): every stencil on its
// own, lambda_i = max(0, (d - D_i) / |grad_i|^2), and each vertex moved by the mean of the
// displacements lambda_i w_ij n_i of the stencils that move it. One ZoneSolution over all the
// stencils' vertices; `feasible` and `max_violation` say whether the averaged move meets every
// constraint (it need not); condition_estimate stays 1 (nothing is factorized).
ZoneSolution projectStencilsIndependently(const std::vector<Stencil>& stencils, double d);

// Conditioning of a zone's matrix A = Dx^T Dx (k by k), from its eigenvalues (dense; zones of up
// to `maxStencils` stencils, else computed = false). condition = lambda_max / lambda_min, +inf
// when A is singular (lambda_min <= 1e-15 lambda_max: duplicate or dependent stencils);
// regularized_condition is that of A + eps I with the solver's Tikhonov eps = 1e-10 max diag(A).
struct ZoneConditioning {
  bool computed = false;
  int stencils = 0;
  double lambda_min = 0, lambda_max = 0;
  double condition = 1;
  double regularized_condition = 1;
};
ZoneConditioning zoneConditioning(const std::vector<Stencil>& stencils, const std::vector<int>& zone,
                                  int maxStencils = 400);

}  // namespace virtual_tryon
