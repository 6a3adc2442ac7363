#include "virtual_tryon/core/scenes/synthetic_scan.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <random>

namespace virtual_tryon {

namespace {

// Uniform in [0, 1) from the top 53 bits (the same on every platform, unlike the standard
// distributions whose algorithms are left to the implementation).
double uniform01(std::mt19937_64& rng) { return static_cast<double>(rng() >> 11) * 0x1.0p-53; }

// Standard normal pairs by Box-Muller; the second value of a pair is kept for the next call.
class Gaussian {
 public:
  double operator()(std::mt19937_64& rng) {
    if (has_spare_) {
      has_spare_ = false;
      return spare_;
    }
    const double u1 = 1.0 - uniform01(rng);  // (0, 1]: log(u1) is finite
    const double u2 = uniform01(rng);
    const double r = std::sqrt(-2.0 * std::log(u1));
    const double a = 2.0 * 3.14159265358979323846 * u2;
    spare_ = r * std::sin(a);
    has_spare_ = true;
    return r * std::cos(a);
  }

 private:
  double spare_ = 0;
  bool has_spare_ = false;
};

}  // namespace

SyntheticScan syntheticScan(const TriMesh& mesh, const SyntheticScanParams& params) {
  SyntheticScan s;
  if (params.points == 0) {
    s.message = "points must be at least 1";
    return s;
  }
  if (!(params.noise_sigma >= 0) || !std::isfinite(params.noise_sigma)) {
    s.message = "noise_sigma must be finite and >= 0 metres, got " + std::to_string(params.noise_sigma);
    return s;
  }
  const MeshValidation v = validate(mesh, "scanned mesh");
  if (!v.ok) {
    s.message = v.message;
    return s;
  }
  const Eigen::Index nf = mesh.F.rows();
  std::vector<double> cumulative(static_cast<std::size_t>(nf));
  double total = 0;
  for (Eigen::Index f = 0; f < nf; ++f) {
    const Eigen::Vector3d a = mesh.V.row(mesh.F(f, 0));
    const Eigen::Vector3d b = mesh.V.row(mesh.F(f, 1));
    const Eigen::Vector3d c = mesh.V.row(mesh.F(f, 2));
    total += 0.5 * (b - a).cross(c - a).norm();
    cumulative[static_cast<std::size_t>(f)] = total;
  }
  s.surface_area = total;
  if (!(total > 0)) {
    s.message = "scanned mesh has zero surface area";
    return s;
  }

  std::mt19937_64 rng(params.seed);
  Gaussian gauss;
  const Eigen::Index n = static_cast<Eigen::Index>(params.points);
  s.points.resize(n, 3);
  s.face.resize(params.points);
  for (Eigen::Index i = 0; i < n; ++i) {
    const double t = uniform01(rng) * total;
    const auto it = std::upper_bound(cumulative.begin(), cumulative.end(), t);
    const Eigen::Index f = std::min<Eigen::Index>(it - cumulative.begin(), nf - 1);
    const double r1 = std::sqrt(uniform01(rng)), r2 = uniform01(rng);
    const Eigen::Vector3d a = mesh.V.row(mesh.F(f, 0));
    const Eigen::Vector3d b = mesh.V.row(mesh.F(f, 1));
    const Eigen::Vector3d c = mesh.V.row(mesh.F(f, 2));
    Eigen::Vector3d p = (1 - r1) * a + r1 * (1 - r2) * b + r1 * r2 * c;
    if (params.noise_sigma > 0) {
      const double gx = gauss(rng), gy = gauss(rng), gz = gauss(rng);
      p += params.noise_sigma * Eigen::Vector3d(gx, gy, gz);
    }
    s.points.row(i) = p.transpose();
    s.face[static_cast<std::size_t>(i)] = static_cast<int>(f);
  }
  s.success = true;
  return s;
}

}  // namespace virtual_tryon
