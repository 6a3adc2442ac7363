#include "virtual_tryon/core/drape/stiffness_spectrum.h"

#include <algorithm>
#include <cmath>
#include <cstdint>

namespace virtual_tryon {

namespace {

// z = M^-1/2 H M^-1/2 w, with s = M^-1/2 (1 / sqrt(mass), 0 where a node has no mass).
void multiply(const MatrixX3d& x, const std::vector<Spring>& springs, const std::vector<double>& k,
              const std::vector<double>& s, const MatrixX3d& w, MatrixX3d& z) {
  z.setZero(w.rows(), 3);
  for (std::size_t i = 0; i < springs.size(); ++i) {
    const Spring& sp = springs[i];
    const Eigen::RowVector3d d = x.row(sp.b) - x.row(sp.a);
    const double l = d.norm();
    if (!(l > 0) || !std::isfinite(l)) continue;
    const Eigen::RowVector3d u = d / l;
    const double across = std::max(0.0, 1.0 - sp.rest / l);
    const Eigen::RowVector3d delta = s[sp.b] * w.row(sp.b) - s[sp.a] * w.row(sp.a);
    const double along = u.dot(delta);
    const Eigen::RowVector3d h = k[i] * (along * u + across * (delta - along * u));
    z.row(sp.b) += s[sp.b] * h;
    z.row(sp.a) -= s[sp.a] * h;
  }
}

}  // namespace

StiffnessSpectrum largestStiffnessEigenvalue(const MatrixX3d& x, const std::vector<Spring>& springs,
                                             const std::vector<double>& k, const std::vector<double>& mass,
                                             int max_iterations, double tolerance) {
  StiffnessSpectrum out;
  const Eigen::Index n = x.rows();
  if (springs.empty() || n == 0 || k.size() != springs.size() || mass.size() != static_cast<std::size_t>(n))
    return out;
  std::vector<double> s(static_cast<std::size_t>(n), 0.0);
  for (std::size_t i = 0; i < s.size(); ++i)
    if (mass[i] > 0 && std::isfinite(mass[i])) s[i] = 1.0 / std::sqrt(mass[i]);
  // A fixed, scrambled start (every mode present, the same estimate on every run).
  MatrixX3d w(n, 3), z;
  std::uint64_t state = 0x9E3779B97F4A7C15ull;
  for (Eigen::Index i = 0; i < n; ++i)
    for (int c = 0; c < 3; ++c) {
      state = state * 6364136223846793005ull + 1442695040888963407ull;
      w(i, c) = static_cast<double>(state >> 11) / 9007199254740992.0 - 0.5;
    }
  w.normalize();
  std::vector<double> history;
  for (int it = 0; it < max_iterations; ++it) {
    multiply(x, springs, k, s, w, z);
    const double rayleigh = w.cwiseProduct(z).sum();
    history.push_back(rayleigh);
    out.lambda_max = std::max(out.lambda_max, rayleigh);
    out.iterations = it + 1;
    const double norm = z.norm();
    if (!(norm > 0) || !std::isfinite(norm)) break;
    w = z / norm;
    if (it >= 10) {
      const double before = history[history.size() - 11];
      out.change = before > 0 ? (rayleigh - before) / rayleigh : 0.0;
      if (out.change < tolerance) break;
    }
  }
  return out;
}

double spectralTimeStep(double lambda_max) {
  return lambda_max > 0 && std::isfinite(lambda_max) ? 2.0 / std::sqrt(lambda_max) : 0.0;
}

}  // namespace virtual_tryon
