#include "virtual_tryon/core/drape/worn_maps.h"

#include "core/geometry/parallel_ranges.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <vector>

namespace virtual_tryon {

void viewBox(MapView v, const Body& body, Eigen::Vector3d& lo, Eigen::Vector3d& hi) {
  lo.setConstant(std::numeric_limits<double>::infinity());
  hi = -lo;
  for (int c = 0; c < 8; ++c) {
    const Eigen::Vector3d corner((c & 1 ? body.boxMax() : body.boxMin()).x(), (c & 2 ? body.boxMax() : body.boxMin()).y(),
                                 (c & 4 ? body.boxMax() : body.boxMin()).z());
    const Eigen::Vector3d q = viewPoint(v, corner);
    lo = lo.cwiseMin(q);
    hi = hi.cwiseMax(q);
  }
}

WornMapRenderer::WornMapRenderer(const WornMapParams& params, const Body& first, double pixel, FrameMaps& firstMaps)
    : params_(params), pixel_(pixel) {
  grid_ = gridAround(first.boxMin(), first.boxMax());
  for (std::size_t k = 0; k < FrameMaps::kOtherViews.size(); ++k) {
    Eigen::Vector3d lo, hi;
    viewBox(FrameMaps::kOtherViews[k], first, lo, hi);
    other_grid_[k] = gridAround(lo, hi);
  }
  firstMaps = renderViews(first, nullptr);
  last_V_ = first.mesh().V;
}

MapGrid WornMapRenderer::gridAround(const Eigen::Vector3d& boxMin, const Eigen::Vector3d& boxMax) const {
  const Eigen::Vector3d grow(params_.grid_margin, params_.grid_margin, 0);
  const Eigen::Vector3d lo = boxMin - grow, hi = boxMax + grow;
  const double extent = std::max(hi.x() - lo.x(), hi.y() - lo.y());
  const int size = std::clamp(static_cast<int>(std::ceil(extent / pixel_ - 1e-9)), 16, 16384);
  return mapGridFor(lo, hi, size, params_.collision.tol);
}

// The views side by side on the hardware threads (each view on its own), or one after the other.
FrameMaps WornMapRenderer::renderViews(const Body& body, const MatrixX3d* velocity) const {
  FrameMaps m;
  std::vector<int> views{-1};  // -1: the front pair; k: kOtherViews[k]
  for (std::size_t k = 0; k < FrameMaps::kOtherViews.size(); ++k)
    if (params_.views[k]) views.push_back(static_cast<int>(k));
  auto renderView = [&](int i) {
    const int k = views[static_cast<std::size_t>(i)];
    if (k < 0) {
      m.front = velocity ? std::make_shared<const DepthMaps>(body.mesh(), params_.collision, grid_, *velocity)
                         : std::make_shared<const DepthMaps>(body.mesh(), params_.collision, grid_);
    } else {
      const auto view = static_cast<std::size_t>(k);
      m.other[view] = std::make_shared<const DepthMaps>(viewMesh(FrameMaps::kOtherViews[view], body.mesh()),
                                                        params_.collision, other_grid_[view]);
    }
  };
  const int n = static_cast<int>(views.size());
  if (params_.parallel) {
    parallelItems(n, 2, renderView);
  } else {
    for (int i = 0; i < n; ++i) renderView(i);
  }
  return m;
}

WornFrameMaps WornMapRenderer::render(const Body& next, double seconds) {
  const auto t0 = std::chrono::steady_clock::now();
  WornFrameMaps out;
  if (!grid_.holds(next.boxMin(), next.boxMax())) {
    grid_ = gridAround(next.boxMin(), next.boxMax());
    out.grid_rebuilt = true;
  }
  for (std::size_t k = 0; k < FrameMaps::kOtherViews.size(); ++k) {
    if (!params_.views[k]) continue;
    Eigen::Vector3d lo, hi;
    viewBox(FrameMaps::kOtherViews[k], next, lo, hi);
    if (!other_grid_[k].holds(lo, hi)) {
      other_grid_[k] = gridAround(lo, hi);
      out.grid_rebuilt = true;
    }
  }
  // The skin's velocity over the interval, for frames of one body (same vertices).
  MatrixX3d velocity;
  out.skin_velocity = params_.skin_velocity && seconds > 0 && last_V_.rows() == next.mesh().V.rows();
  if (out.skin_velocity) velocity = (next.mesh().V - last_V_) / seconds;
  out.maps = renderViews(next, out.skin_velocity ? &velocity : nullptr);
  out.body_V = next.mesh().V;
  out.seconds = seconds;
  last_V_ = out.body_V;
  out.seconds_render = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return out;
}

void WornMapRenderer::adopt(const WornFrameMaps& maps) {
  if (maps.maps.front) grid_ = maps.maps.front->grid();
  for (std::size_t k = 0; k < FrameMaps::kOtherViews.size(); ++k)
    if (maps.maps.other[k]) other_grid_[k] = maps.maps.other[k]->grid();
  last_V_ = maps.body_V;
}

}  // namespace virtual_tryon
