// The explicit step's stability limit from the springs' stiffness matrix
// (core/drape/stiffness_spectrum.h): the analytic spectrum of a chain, the dense eigenvalues of the
// finite-difference Jacobian of the cloth's forces, the step stable just below the limit and
// blowing up just above it, and degenerate input.
#include "virtual_tryon/core/drape/cloth.h"
#include "virtual_tryon/core/drape/stiffness_spectrum.h"

#include "cloth_helpers.h"

#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>

#include <cmath>
#include <random>
#include <vector>

using namespace virtual_tryon;
using virtual_tryon_test::gridCloth;

namespace {

double stiffnessOf(const ClothParams& p, SpringType t) {
  return t == SpringType::Structural ? p.k_structural : t == SpringType::Shear ? p.k_shear : p.k_flexion;
}

std::vector<double> stiffnesses(const std::vector<Spring>& springs, const ClothParams& p) {
  std::vector<double> k;
  for (const Spring& s : springs) k.push_back(stiffnessOf(p, s.type));
  return k;
}

// A quiet cloth: no gravity, no damping, no velocity fix (the step alone).
ClothParams bareParams() {
  ClothParams p;
  p.gravity.setZero();
  p.damping_rate = 0;
  p.sewing_damping_rate = 0;
  p.velocity_fix_passes = 0;
  return p;
}

}  // namespace

TEST(StiffnessSpectrum, AChainAlongAnyAxisHasTheAnalyticLargestEigenvalue) {
  // N equal masses joined by N - 1 equal springs at rest: lambda_j = 4 k / m sin^2(j pi / 2N).
  const int n = 12;
  const double k = 50.0, m = 2e-3, h = 0.03;
  const double exact = 4 * k / m * std::pow(std::sin((n - 1) * M_PI / (2.0 * n)), 2);
  std::vector<Spring> springs;
  for (int i = 0; i + 1 < n; ++i) springs.push_back({i, i + 1, h, SpringType::Structural});
  const std::vector<double> ks(springs.size(), k), masses(n, m);
  for (const Eigen::RowVector3d& axis :
       {Eigen::RowVector3d(1, 0, 0), Eigen::RowVector3d(Eigen::RowVector3d(0.3, -0.8, 0.5).normalized())}) {
    MatrixX3d x(n, 3);
    for (int i = 0; i < n; ++i) x.row(i) = i * h * axis;
    const StiffnessSpectrum tight = largestStiffnessEigenvalue(x, springs, ks, masses, 3000, 0.0);
    EXPECT_NEAR(tight.lambda_max, exact, 1e-9 * exact) << axis;
    const StiffnessSpectrum quick = largestStiffnessEigenvalue(x, springs, ks, masses);  // the defaults
    EXPECT_LE(quick.lambda_max, exact * (1 + 1e-12)) << "a Rayleigh quotient is never above lambda_max";
    EXPECT_GT(quick.lambda_max, 0.99 * exact) << quick.iterations << " iterations";
    EXPECT_LT(quick.iterations, 400);
    EXPECT_NEAR(spectralTimeStep(tight.lambda_max), 2 / std::sqrt(exact), 1e-9 / std::sqrt(exact));
  }
}

TEST(StiffnessSpectrum, IsTheLargestDenseEigenvalueOfTheForcesJacobian) {
  // A 4 x 4 grid stretched by a fifth and jittered (every spring longer than rest, so that the
  // across-the-spring tension counts): M^-1/2 (-df/dx) M^-1/2 by central differences of the
  // cloth's own forces, against the power iteration on the closed-form Hessian.
  ClothMesh mesh = gridCloth(4, 0.05);
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> jitter(-0.004, 0.004);
  mesh.X *= 1.2;
  for (Eigen::Index i = 0; i < mesh.X.rows(); ++i) mesh.X.row(i) += Eigen::RowVector3d(jitter(rng), jitter(rng), jitter(rng));
  const ClothParams p = bareParams();
  ClothState cloth(mesh, p);
  const Eigen::Index n = mesh.X.rows();
  Eigen::MatrixXd A(3 * n, 3 * n);
  const double step = 1e-6;
  for (Eigen::Index j = 0; j < 3 * n; ++j) {
    double& xj = cloth.positions()(j / 3, j % 3);
    const double x0 = xj;
    xj = x0 + step;
    const MatrixX3d fp = cloth.evaluateForces();
    xj = x0 - step;
    const MatrixX3d fm = cloth.evaluateForces();
    xj = x0;
    for (Eigen::Index i = 0; i < 3 * n; ++i)
      A(i, j) = -(fp(i / 3, i % 3) - fm(i / 3, i % 3)) / (2 * step) /
                std::sqrt(cloth.masses()[static_cast<std::size_t>(i / 3)] * cloth.masses()[static_cast<std::size_t>(j / 3)]);
  }
  EXPECT_LT((A - A.transpose()).cwiseAbs().maxCoeff(), 1e-5 * A.cwiseAbs().maxCoeff());
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(0.5 * (A + A.transpose()));
  const double dense = eig.eigenvalues().maxCoeff();
  const StiffnessSpectrum power =
      largestStiffnessEigenvalue(cloth.positions(), cloth.springs(), stiffnesses(cloth.springs(), p), cloth.masses(), 5000, 0.0);
  EXPECT_NEAR(power.lambda_max, dense, 1e-5 * dense);
  EXPECT_NEAR(cloth.spectralTimeStep(), 2 / std::sqrt(dense), 2e-3 * 2 / std::sqrt(dense));  // the defaults
  // Gershgorin's per-node bound is on the safe side of it, and well inside it on a grid.
  EXPECT_LT(cloth.stableTimeStep(), 0.8 * cloth.spectralTimeStep());
}

TEST(StiffnessSpectrum, TheStepIsStableJustBelowTheLimitAndBlowsUpJustAbove) {
  // A free 8 x 8 cloth at rest, every node nudged by up to 0.1 mm (every mode present), the bare
  // explicit step (no damping, no velocity fix) for 3000 steps.
  ClothMesh mesh = gridCloth(8, 0.02);
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> nudge(-1e-4, 1e-4);
  for (Eigen::Index i = 0; i < mesh.X.rows(); ++i) mesh.X.row(i) += Eigen::RowVector3d(nudge(rng), nudge(rng), nudge(rng));
  const ClothParams p = bareParams();
  const double limit = ClothState(mesh, p).spectralTimeStep();
  ASSERT_GT(limit, 0);
  auto run = [&](double dt, double& fastest) {
    ClothState cloth(mesh, p);
    fastest = 0;
    for (int it = 0; it < 3000; ++it) {
      if (!cloth.step(dt, false)) return false;
      fastest = std::max(fastest, cloth.maxSpeed());
    }
    return true;
  };
  double fastest = 0;
  EXPECT_TRUE(run(0.95 * limit, fastest)) << "blew up at 0.95 of the limit";
  EXPECT_LT(fastest, 1.0) << "m/s at 0.95 of the limit";
  EXPECT_FALSE(run(1.05 * limit, fastest)) << "still bounded at 1.05 of the limit, fastest " << fastest << " m/s";
  ClothState probe(mesh, p);
  EXPECT_GT(limit, 1.3 * probe.stableTimeStep()) << "the per-node bound is this far inside on a grid";
}

TEST(StiffnessSpectrum, DegenerateInputGivesNothingOrSkipsTheSpring) {
  const MatrixX3d none(0, 3);
  EXPECT_EQ(largestStiffnessEigenvalue(none, {}, {}, {}).lambda_max, 0.0);
  MatrixX3d x(3, 3);
  x << 0, 0, 0, 0.1, 0, 0, 0.1, 0, 0;  // the second spring has zero length
  const std::vector<Spring> springs{{0, 1, 0.1, SpringType::Structural}, {1, 2, 0.1, SpringType::Structural}};
  const std::vector<double> m{1e-3, 1e-3, 1e-3};
  EXPECT_EQ(largestStiffnessEigenvalue(x, springs, {10.0}, m).lambda_max, 0.0) << "a stiffness per spring";
  EXPECT_EQ(largestStiffnessEigenvalue(x, springs, {10.0, 10.0}, {1e-3}).lambda_max, 0.0) << "a mass per node";
  const StiffnessSpectrum one = largestStiffnessEigenvalue(x, springs, {10.0, 10.0}, m, 3000, 0.0);
  EXPECT_NEAR(one.lambda_max, 2 * 10.0 / 1e-3, 1e-6) << "the zero-length spring adds nothing";
  x(2, 0) = std::nan("");
  const StiffnessSpectrum nan = largestStiffnessEigenvalue(x, springs, {10.0, 10.0}, m, 3000, 0.0);
  EXPECT_NEAR(nan.lambda_max, 2 * 10.0 / 1e-3, 1e-6) << "a spring to a non-finite node adds nothing";
  EXPECT_EQ(spectralTimeStep(0.0), 0.0);
  EXPECT_EQ(spectralTimeStep(-1.0), 0.0);
  EXPECT_EQ(spectralTimeStep(std::nan("")), 0.0);
}
