#include "virtual_tryon/core/body/scan_error.h"

#include "virtual_tryon/core/body/body.h"
#include "virtual_tryon/core/geometry/point_queries.h"

#include <pcl/kdtree/kdtree_flann.h>
#include <pcl/point_cloud.h>
#include <pcl/point_types.h>

#include <Eigen/Dense>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <exception>
#include <vector>

namespace virtual_tryon {
namespace {

using Clock = std::chrono::steady_clock;
double since(const Clock::time_point& t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

// The finite rows of `points`, as their indices.
std::vector<Eigen::Index> finiteRows(const MatrixX3d& points) {
  std::vector<Eigen::Index> rows;
  rows.reserve(static_cast<std::size_t>(points.rows()));
  for (Eigen::Index i = 0; i < points.rows(); ++i)
    if (points.row(i).allFinite()) rows.push_back(i);
  return rows;
}

// An even stride through `n` items giving at most `cap` of them (cap 0: all).
std::size_t strideFor(std::size_t n, std::size_t cap) { return cap == 0 || n <= cap ? 1 : (n + cap - 1) / cap; }

// The residual of p against the quadric w = a u^2 + b uv + c v^2 + d u + e v + f fitted to its
// neighbours `q` (k by 3) in their principal frame, divided by sqrt(1 + leverage); false when the
// fit is degenerate.
bool quadricResidual(const Eigen::Vector3d& p, const Eigen::MatrixX3d& q, double& residual) {
  const Eigen::RowVector3d c = q.colwise().mean();
  const Eigen::MatrixX3d centred = q.rowwise() - c;
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> pca(centred.transpose() * centred);
  if (pca.info() != Eigen::Success) return false;
  const Eigen::Matrix3d frame = pca.eigenvectors();  // columns: normal (smallest), then tangents
  const Eigen::MatrixX3d local = centred * frame;    // (w, u, v) per neighbour
  Eigen::MatrixXd X(q.rows(), 6);
  for (Eigen::Index j = 0; j < q.rows(); ++j) {
    const double u = local(j, 1), v = local(j, 2);
    X.row(j) << u * u, u * v, v * v, u, v, 1.0;
  }
  const Eigen::Vector3d lp = frame.transpose() * (p - c.transpose());
  Eigen::Matrix<double, 6, 1> x;
  x << lp(1) * lp(1), lp(1) * lp(2), lp(2) * lp(2), lp(1), lp(2), 1.0;
  const Eigen::LDLT<Eigen::MatrixXd> normal(X.transpose() * X);
  if (normal.info() != Eigen::Success || !(normal.rcond() > 1e-12)) return false;
  const Eigen::VectorXd coef = normal.solve(X.transpose() * local.col(0));
  const double leverage = x.dot(normal.solve(x));
  if (!std::isfinite(leverage) || leverage < 0) return false;
  residual = (lp(0) - x.dot(coef)) / std::sqrt(1.0 + leverage);
  return std::isfinite(residual);
}

}  // namespace

ScanNoiseEstimate estimateScanNoise(const MatrixX3d& points, std::size_t max_samples, int neighbours) {
  const auto t0 = Clock::now();
  ScanNoiseEstimate est;
  const int k = std::max(10, neighbours);
  try {
    const std::vector<Eigen::Index> rows = finiteRows(points);
    if (rows.size() < static_cast<std::size_t>(k) + 1) return est;
    // PointNormal, the point type scan_meshing.cpp already uses: a PointCloud<PointXYZ> made here
    // would share its template code with libpcl_io's own (STL files), compiled for another Eigen
    // alignment, and the two would free each other's points (AddressSanitizer saw it).
    pcl::PointCloud<pcl::PointNormal>::Ptr cloud(new pcl::PointCloud<pcl::PointNormal>);
    cloud->reserve(rows.size());
    for (Eigen::Index i : rows) {
      pcl::PointNormal p;
      p.x = static_cast<float>(points(i, 0)), p.y = static_cast<float>(points(i, 1));
      p.z = static_cast<float>(points(i, 2));
      p.normal_x = p.normal_y = 0, p.normal_z = 1, p.curvature = 0;
      cloud->push_back(p);
    }
    pcl::KdTreeFLANN<pcl::PointNormal> tree;
    tree.setInputCloud(cloud);
    pcl::Indices idx;
    std::vector<float> d2;
    std::vector<double> residuals;
    const std::size_t stride = strideFor(rows.size(), max_samples);
    for (std::size_t s = 0; s < rows.size(); s += stride) {
      if (tree.nearestKSearch((*cloud)[s], k + 1, idx, d2) < k + 1) continue;
      Eigen::MatrixX3d q(k, 3);
      int m = 0;
      for (std::size_t j = 0; j < idx.size() && m < k; ++j)
        if (static_cast<std::size_t>(idx[j]) != s) q.row(m++) = points.row(rows[static_cast<std::size_t>(idx[j])]);
      if (m < k) continue;
      double r = 0;
      if (quadricResidual(points.row(rows[s]).transpose(), q, r)) residuals.push_back(std::abs(r));
    }
    if (residuals.empty()) return est;
    auto mid = residuals.begin() + static_cast<std::ptrdiff_t>(residuals.size() / 2);
    std::nth_element(residuals.begin(), mid, residuals.end());
    est.sigma = *mid / 0.6744897501960817;
    est.samples = residuals.size();
  } catch (const std::exception&) {
    est = ScanNoiseEstimate();
  }
  est.seconds = since(t0);
  return est;
}

ScanError measureScanError(const MatrixX3d& points, const TriMesh& mesh, std::size_t max_points) {
  const auto t0 = Clock::now();
  ScanError e;
  if (mesh.F.rows() == 0) return e;
  const std::vector<Eigen::Index> rows = finiteRows(points);
  const std::size_t stride = strideFor(rows.size(), max_points);
  const Body body(mesh);
  std::vector<double> d;
  d.reserve(rows.size() / stride + 1);
  std::size_t over = 0;
  for (std::size_t s = 0; s < rows.size(); s += stride) {
    d.push_back(closestPointOnBody(body, points.row(rows[s]).transpose()).distance);
    over += d.back() > 0.002;
  }
  if (d.empty()) return e;
  std::sort(d.begin(), d.end());
  auto rank = [&d](double q) {  // nearest rank
    const auto i = static_cast<std::size_t>(std::ceil(q * static_cast<double>(d.size())));
    return d[std::min(d.size() - 1, i > 0 ? i - 1 : 0)];
  };
  e.points = d.size();
  e.median = rank(0.5);
  e.p95 = rank(0.95);
  e.max = d.back();
  e.share_over_2mm = static_cast<double>(over) / static_cast<double>(d.size());
  e.seconds = since(t0);
  return e;
}

}  // namespace virtual_tryon
