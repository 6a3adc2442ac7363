// The explicit step's real stability limit for a mass-spring cloth: the largest eigenvalue of
// M^-1 H, with H the springs' stiffness matrix (the Hessian of sum 1/2 k (l - l0)^2) at the
// positions x and M the lumped node masses.
//
// One spring's Hessian block, d = x_b - x_a, l = |d|, u = d / l:
//   H_s = k (u u^T + max(0, 1 - l0 / l) (I - u u^T)),   on [x_a; x_b] as [H_s -H_s; -H_s H_s]
// (along the spring k; across it the tension's k (1 - l0 / l), whose negative part, a squeezed
// spring's buckling, is not an overshoot of the step and is left out).
// The symplectic Euler step of eq. 3 is stable for a mode of angular frequency w when w dt <= 2,
// so the step is stable up to 2 / sqrt(lambda_max). The per-node bound (ClothState::
// stableTimeStep, Gershgorin's row sum) treats every spring as pulling along every axis; a spring
// resists mainly along itself, and on a cloth grid lambda_max is about half of that row sum.
//
// lambda_max is estimated by power iteration on the symmetric M^-1/2 H M^-1/2 from a fixed start;
// the Rayleigh quotient approaches lambda_max from below, so callers keep a safety factor.
#pragma once

#include "virtual_tryon/core/drape/pattern.h"

#include <vector>

namespace virtual_tryon {

struct StiffnessSpectrum {
  double lambda_max = 0;  // 1/s^2: the estimate of M^-1 H's largest eigenvalue
  int iterations = 0;     // power iterations run
  double change = 0;      // relative change of the estimate over the last ten iterations
};

// x: #N by 3 node positions; springs with stiffness k[s] (N/m, one per spring); mass: #N (kg, > 0
// for every node a spring meets). Iterates until the estimate changes by less than `tolerance`
// (relative) over ten iterations, or `max_iterations`. Nothing (lambda_max 0) without springs.
StiffnessSpectrum largestStiffnessEigenvalue(const MatrixX3d& x, const std::vector<Spring>& springs,
                                             const std::vector<double>& k, const std::vector<double>& mass,
                                             int max_iterations = 400, double tolerance = 1e-3);

// 2 / sqrt(lambda_max): the symplectic Euler limit; 0 for lambda_max <= 0.
double spectralTimeStep(double lambda_max);

}  // namespace virtual_tryon
