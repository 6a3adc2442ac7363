// nearestVertices (core/geometry/point_queries.h): against a brute-force search (up to the k-d tree's
// single precision), on clouds dense and sparse, points near and far, and the empty case.
#include "virtual_tryon/core/geometry/point_queries.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

using namespace virtual_tryon;

TEST(NearestVertices, MatchesBruteForce) {
  std::mt19937 rng(3);
  std::normal_distribution<double> g(0.0, 1.0);
  for (int n : {1, 7, 500, 5000}) {
    MatrixX3d V(n, 3), P(300, 3);
    for (int i = 0; i < n; ++i) V.row(i) << g(rng), 0.2 * g(rng), 3 * g(rng);
    for (int i = 0; i < P.rows(); ++i) P.row(i) << 4 * g(rng), g(rng), 10 * g(rng);  // many outside the cloud
    const std::vector<int> got = nearestVertices(V, P);
    ASSERT_EQ(got.size(), 300u);
    for (int i = 0; i < P.rows(); ++i) {
      Eigen::Index best = 0;
      const double d = (V.rowwise() - P.row(i)).rowwise().squaredNorm().minCoeff(&best);
      ASSERT_GE(got[i], 0);
      EXPECT_NEAR(std::sqrt((V.row(got[i]) - P.row(i)).squaredNorm()), std::sqrt(d), 1e-5 * (1 + std::sqrt(d))) << n << " " << i;
    }
  }
  EXPECT_EQ(nearestVertices(MatrixX3d(0, 3), MatrixX3d::Zero(2, 3)), std::vector<int>(2, -1));
  // All vertices at one point: any of them.
  const int any = nearestVertices(MatrixX3d::Ones(4, 3), MatrixX3d::Zero(1, 3))[0];
  EXPECT_TRUE(any >= 0 && any < 4);
}
