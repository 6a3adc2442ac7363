#include "core/resolve/face_clearance.h"

#include "core/geometry/face_box_tree.h"
#include "core/geometry/body_bvh.h"

#include <algorithm>
#include <cmath>

namespace virtual_tryon {
namespace resolver_run {
namespace {

// The face must meet the body vertex's normal at least this steeply (the sine of the angle between
// its plane and the normal); a face nearly along the normal has no point "above" the vertex.
constexpr double kMinFaceTilt = 0.2;

}  // namespace

void faceClearances(const Body& body, const TriMesh& garment, int f, double c, std::vector<FaceClearance>& out) {
  const TriMesh& B = body.mesh();
  const Eigen::Vector3d x0 = garment.V.row(garment.F(f, 0)).transpose(), x1 = garment.V.row(garment.F(f, 1)).transpose(),
                        x2 = garment.V.row(garment.F(f, 2)).transpose();
  const Eigen::Vector3d e1 = x1 - x0, e2 = x2 - x0, fn = e1.cross(e2);
  const double fn2 = fn.squaredNorm();
  if (!(fn2 > 0)) return;
  const Eigen::Vector3d lo = x0.cwiseMin(x1).cwiseMin(x2).array() - c, hi = x0.cwiseMax(x1).cwiseMax(x2).array() + c;
  std::vector<int> corners;
  body.bvh().faceTree().overlapping(lo, hi, [&](int bf) {
    for (int k = 0; k < 3; ++k) corners.push_back(B.F(bf, k));
  });
  std::sort(corners.begin(), corners.end());
  corners.erase(std::unique(corners.begin(), corners.end()), corners.end());
  for (int y : corners) {
    const Eigen::Vector3d n = body.vertexNormal(y), py = B.V.row(y).transpose();
    const double denom = fn.dot(n);
    if (std::abs(denom) < kMinFaceTilt * std::sqrt(fn2)) continue;
    const double t = fn.dot(x0 - py) / denom;  // py + t n lies in the face's plane
    if (!(t < c) || !(t > -c)) continue;
    const Eigen::Vector3d q = py + t * n - x0;
    const double w1 = q.cross(e2).dot(fn) / fn2, w2 = e1.cross(q).dot(fn) / fn2, w0 = 1 - w1 - w2;
    if (w0 < 0 || w1 < 0 || w2 < 0) continue;
    FaceClearance k;
    k.face = f;
    k.body_vertex = y;
    k.weight = {{w0, w1, w2}};
    k.normal = n;
    k.bound = n.dot(py) + c;
    out.push_back(k);
  }
}

double cornerReach(const TriMesh& garment, int f, int k) {
  const int c = garment.F(f, k);
  return std::max((garment.V.row(c) - garment.V.row(garment.F(f, (k + 1) % 3))).norm(),
                  (garment.V.row(c) - garment.V.row(garment.F(f, (k + 2) % 3))).norm());
}

double shortfall(const FaceClearance& k, const TriMesh& garment) {
  double value = 0;
  for (int i = 0; i < 3; ++i) value += k.weight[i] * k.normal.dot(garment.V.row(garment.F(k.face, i)).transpose());
  return k.bound - value;
}

}  // namespace resolver_run
}  // namespace virtual_tryon
