#include "virtual_tryon/testing/push_out_baseline.h"

#include "virtual_tryon/core/geometry/point_queries.h"

#include <algorithm>
#include <chrono>
#include <vector>

namespace virtual_tryon {

PushOutReport pushOutBaseline(const Body& body, TriMesh& garment, const PushOutParams& params) {
  using Clock = std::chrono::steady_clock;
  const auto t0 = Clock::now();
  PushOutReport rep;
  rep.body_closed = body.closed();
  rep.margin = params.margin > 0 ? params.margin : params.margin_fraction * meanEdgeLength(garment);
  const MatrixX3d& N = body.faceNormals();
  std::vector<std::pair<int, Eigen::Vector3d>> moves;
  for (Eigen::Index v = 0; v < garment.V.rows(); ++v) {
    const Eigen::Vector3d x = garment.V.row(v).transpose();
    // Inside: by parity on a closed body, else behind the nearest face.
    if (rep.body_closed && !pointInsideBody(body, x)) continue;
    const ClosestPoint cp = closestPointOnBody(body, x);
    if (cp.face < 0) continue;
    if (!rep.body_closed && N.row(cp.face).dot((x - cp.point).transpose()) >= 0) continue;
    moves.emplace_back(static_cast<int>(v), cp.point + rep.margin * N.row(cp.face).transpose());
  }
  rep.seconds_detection = std::chrono::duration<double>(Clock::now() - t0).count();
  double sum = 0;
  for (const auto& [v, to] : moves) {
    const double len = (to.transpose() - garment.V.row(v)).norm();
    garment.V.row(v) = to.transpose();
    sum += len;
    rep.max_displacement = std::max(rep.max_displacement, len);
  }
  rep.vertices_inside = moves.size();
  rep.mean_displacement = moves.empty() ? 0.0 : sum / static_cast<double>(moves.size());
  rep.seconds_total = std::chrono::duration<double>(Clock::now() - t0).count();
  return rep;
}

}  // namespace virtual_tryon
