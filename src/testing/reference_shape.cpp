#include "virtual_tryon/testing/reference_shape.h"

#include "virtual_tryon/core/io/json_object.h"

#include "testing/reference_predicates.h"

#include <algorithm>
#include <cmath>
#include <vector>

namespace virtual_tryon {
namespace {

void measureStrain(const TriMesh& input, const TriMesh& output, ReferenceShape& s) {
  const MatrixX2i E = uniqueEdges(input);
  std::vector<double> strain;
  strain.reserve(static_cast<std::size_t>(E.rows()));
  for (Eigen::Index e = 0; e < E.rows(); ++e) {
    const double l0 = (input.V.row(E(e, 0)) - input.V.row(E(e, 1))).norm();
    if (!(l0 > 0)) continue;
    const double l = (output.V.row(E(e, 0)) - output.V.row(E(e, 1))).norm();
    strain.push_back(std::abs(l / l0 - 1));
  }
  s.edges = strain.size();
  if (strain.empty()) return;
  std::sort(strain.begin(), strain.end());
  s.max_strain = strain.back();
  const std::size_t rank = static_cast<std::size_t>(std::ceil(0.99 * static_cast<double>(strain.size())));
  s.p99_strain = strain[std::max<std::size_t>(rank, 1) - 1];
}

// Area-weighted vertex normals of the body (its own, not the core's Body).
MatrixX3d bodyVertexNormals(const TriMesh& body) {
  MatrixX3d N = MatrixX3d::Zero(body.V.rows(), 3);
  for (Eigen::Index f = 0; f < body.F.rows(); ++f) {
    const Eigen::RowVector3d a = body.V.row(body.F(f, 0)), b = body.V.row(body.F(f, 1)), c = body.V.row(body.F(f, 2));
    const Eigen::RowVector3d n = (b - a).cross(c - a);
    for (int k = 0; k < 3; ++k) N.row(body.F(f, k)) += n;
  }
  return N;
}

// The largest distance from a crossed input garment face's plane to the outer end of a body edge
// that crosses it.
double bodyEdgeNeed(const TriMesh& body, const TriMesh& input) {
  const ReferenceTree tree(input);
  const MatrixX2i E = uniqueEdges(body);
  const MatrixX3d N = bodyVertexNormals(body);
  double need = 0;
  for (Eigen::Index e = 0; e < E.rows(); ++e) {
    const Eigen::Vector3d y0 = body.V.row(E(e, 0)).transpose(), y1 = body.V.row(E(e, 1)).transpose();
    const Eigen::Vector3d dir = y1 - y0;
    const Eigen::Vector3d outward = (N.row(E(e, 0)) + N.row(E(e, 1))).transpose();
    const Eigen::Vector3d outer = outward.dot(dir) >= 0 ? y1 : y0;
    tree.alongSegment(y0, dir, [&](int f) {
      const Eigen::Vector3d a = input.V.row(input.F(f, 0)).transpose(), b = input.V.row(input.F(f, 1)).transpose(),
                            c = input.V.row(input.F(f, 2)).transpose();
      if (!reference_predicates::mtHit(y0, dir, a, b, c, 1e-12)) return;
      const Eigen::Vector3d n = (b - a).cross(c - a);
      if (n.squaredNorm() == 0) return;
      need = std::max(need, std::abs(n.normalized().dot(outer - a)));
    });
  }
  return need;
}

}  // namespace

ReferenceShape referenceShape(const ReferenceReferee& referee, const TriMesh& input, const TriMesh& output,
                              bool closedBody, const ReferenceShapeParams& params) {
  ReferenceShape s;
  measureStrain(input, output, s);
  const Eigen::Index nv = std::min(input.V.rows(), output.V.rows());
  const std::vector<double> dist = referee.signedDistances(input);
  double sum = 0;
  for (Eigen::Index v = 0; v < nv; ++v) {
    const double len = (output.V.row(v) - input.V.row(v)).norm();
    sum += len;
    s.max_displacement = std::max(s.max_displacement, len);
    if (len > 0) ++s.moved_vertices;
    const double dv = dist[static_cast<std::size_t>(v)];
    if (closedBody && dv < 0) s.need_inside = std::max(s.need_inside, -dv);
    if (std::abs(dv) > params.far_distance && len > params.moved_distance) ++s.far_vertices_moved;
  }
  s.mean_displacement = nv ? sum / static_cast<double>(nv) : 0.0;
  s.need_body_edges = bodyEdgeNeed(referee.body(), input);
  s.need = std::max(s.need_inside, s.need_body_edges);
  return s;
}

std::string toJson(const ReferenceShape& s) {
  return json::Obj()
      .add("edges", s.edges)
      .add("max_strain", s.max_strain)
      .add("p99_strain", s.p99_strain)
      .add("mean_displacement_m", s.mean_displacement)
      .add("max_displacement_m", s.max_displacement)
      .add("moved_vertices", s.moved_vertices)
      .add("need_m", s.need)
      .add("need_inside_m", s.need_inside)
      .add("need_body_edges_m", s.need_body_edges)
      .add("far_vertices_moved", s.far_vertices_moved)
      .str();
}

}  // namespace virtual_tryon
