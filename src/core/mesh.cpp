#include "virtual_tryon/core/mesh.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <numeric>
#include <sstream>

namespace virtual_tryon {

MeshValidation validate(const TriMesh& mesh, const std::string& what) {
  MeshValidation r;
  std::ostringstream msg;
  if (mesh.V.rows() == 0) {
    r.ok = false;
    r.message = what + " has no vertices";
    return r;
  }
  if (mesh.F.rows() == 0) {
    r.ok = false;
    r.message = what + " has no faces (" + std::to_string(mesh.V.rows()) + " vertices)";
    return r;
  }
  for (Eigen::Index i = 0; i < mesh.V.rows(); ++i)
    if (!mesh.V.row(i).allFinite()) ++r.non_finite_vertices;
  if (r.non_finite_vertices > 0) {
    r.ok = false;
    msg << what << " has " << r.non_finite_vertices << " vertices with NaN or Inf coordinates";
    r.message = msg.str();
    return r;
  }
  const Eigen::Index n = mesh.V.rows();
  std::vector<char> used(static_cast<std::size_t>(n), 0);
  Eigen::Index firstBad = -1;
  for (Eigen::Index f = 0; f < mesh.F.rows(); ++f)
    for (int k = 0; k < 3; ++k) {
      const int i = mesh.F(f, k);
      if (i < 0 || i >= n) {
        ++r.out_of_range_indices;
        if (firstBad < 0) firstBad = f;
      } else {
        used[static_cast<std::size_t>(i)] = 1;
      }
    }
  if (r.out_of_range_indices > 0) {
    r.ok = false;
    msg << what << " has " << r.out_of_range_indices << " vertex indices out of range [0, " << n
        << ") (first in face " << firstBad << ")";
    r.message = msg.str();
    return r;
  }
  Eigen::Vector3d lo, hi;
  boundingBox(mesh, lo, hi);
  const double scale = std::max((hi - lo).norm(), 1e-300);
  const double areaTol = 1e-14 * scale * scale;
  for (Eigen::Index f = 0; f < mesh.F.rows(); ++f) {
    const int a = mesh.F(f, 0), b = mesh.F(f, 1), c = mesh.F(f, 2);
    if (a == b || b == c || a == c) {
      ++r.degenerate_faces;
      continue;
    }
    const Eigen::Vector3d e1 = mesh.V.row(b) - mesh.V.row(a);
    const Eigen::Vector3d e2 = mesh.V.row(c) - mesh.V.row(a);
    if (0.5 * e1.cross(e2).norm() <= areaTol) ++r.degenerate_faces;
  }
  r.unused_vertices = static_cast<std::size_t>(std::count(used.begin(), used.end(), 0));
  if (r.degenerate_faces > 0 || r.unused_vertices > 0) {
    msg << what << ": " << r.degenerate_faces << " degenerate faces, " << r.unused_vertices
        << " unused vertices";
    r.message = msg.str();
  }
  return r;
}

MatrixX3d faceNormals(const TriMesh& mesh) {
  MatrixX3d N(mesh.F.rows(), 3);
  for (Eigen::Index f = 0; f < mesh.F.rows(); ++f) {
    const Eigen::Vector3d a = mesh.V.row(mesh.F(f, 0));
    const Eigen::Vector3d n = (Eigen::Vector3d(mesh.V.row(mesh.F(f, 1))) - a)
                                  .cross(Eigen::Vector3d(mesh.V.row(mesh.F(f, 2))) - a);
    const double len = n.norm();
    N.row(f) = len > 0 ? Eigen::Vector3d(n / len) : Eigen::Vector3d::Zero();
  }
  return N;
}

MatrixX3d vertexNormals(const TriMesh& mesh) {
  MatrixX3d N = MatrixX3d::Zero(mesh.V.rows(), 3);
  for (Eigen::Index f = 0; f < mesh.F.rows(); ++f) {
    const Eigen::Vector3d a = mesh.V.row(mesh.F(f, 0));
    const Eigen::Vector3d n = (Eigen::Vector3d(mesh.V.row(mesh.F(f, 1))) - a)
                                  .cross(Eigen::Vector3d(mesh.V.row(mesh.F(f, 2))) - a);
    for (int k = 0; k < 3; ++k) N.row(mesh.F(f, k)) += n;  // |n| = 2 * area
  }
  for (Eigen::Index i = 0; i < N.rows(); ++i) {
    const double len = N.row(i).norm();
    if (len > 0) N.row(i) /= len;
  }
  return N;
}

MatrixX2i uniqueEdges(const TriMesh& mesh, MatrixX3i* faceEdges) {
  const Eigen::Index nf = mesh.F.rows();
  std::vector<std::pair<std::pair<int, int>, Eigen::Index>> half;  // ((lo, hi), 3f + k)
  half.reserve(static_cast<std::size_t>(3 * nf));
  for (Eigen::Index f = 0; f < nf; ++f)
    for (int k = 0; k < 3; ++k) {
      const int a = mesh.F(f, k), b = mesh.F(f, (k + 1) % 3);
      half.push_back({{std::min(a, b), std::max(a, b)}, 3 * f + k});
    }
  std::sort(half.begin(), half.end());
  MatrixX2i E(static_cast<Eigen::Index>(half.size()), 2);
  if (faceEdges) faceEdges->resize(nf, 3);
  Eigen::Index ne = 0;
  for (std::size_t i = 0; i < half.size(); ++i) {
    if (i == 0 || half[i].first != half[i - 1].first) {
      E(ne, 0) = half[i].first.first;
      E(ne, 1) = half[i].first.second;
      ++ne;
    }
    if (faceEdges) (*faceEdges)(half[i].second / 3, half[i].second % 3) = static_cast<int>(ne - 1);
  }
  E.conservativeResize(ne, 2);
  return E;
}

double meanEdgeLength(const TriMesh& mesh) {
  const MatrixX2i E = uniqueEdges(mesh);
  if (E.rows() == 0) return 0.0;
  double sum = 0;
  for (Eigen::Index e = 0; e < E.rows(); ++e) sum += (mesh.V.row(E(e, 0)) - mesh.V.row(E(e, 1))).norm();
  return sum / static_cast<double>(E.rows());
}

EdgeTopology edgeTopology(const TriMesh& mesh) {
  MatrixX3i FE;
  const MatrixX2i E = uniqueEdges(mesh, &FE);
  std::vector<int> count(static_cast<std::size_t>(E.rows()), 0);
  for (Eigen::Index f = 0; f < FE.rows(); ++f)
    for (int k = 0; k < 3; ++k) ++count[static_cast<std::size_t>(FE(f, k))];
  EdgeTopology t;
  for (int c : count) {
    if (c == 1) ++t.boundary_edges;
    if (c > 2) ++t.non_manifold_edges;
  }
  return t;
}

double signedVolume(const TriMesh& mesh) {
  double v = 0;
  for (Eigen::Index f = 0; f < mesh.F.rows(); ++f) {
    const Eigen::Vector3d a = mesh.V.row(mesh.F(f, 0)), b = mesh.V.row(mesh.F(f, 1)),
                          c = mesh.V.row(mesh.F(f, 2));
    v += a.dot(b.cross(c));
  }
  return v / 6.0;
}

void boundingBox(const TriMesh& mesh, Eigen::Vector3d& lo, Eigen::Vector3d& hi) {
  if (mesh.V.rows() == 0) {
    lo.setZero();
    hi.setZero();
    return;
  }
  lo = mesh.V.colwise().minCoeff().transpose();
  hi = mesh.V.colwise().maxCoeff().transpose();
}

int connectedComponents(const TriMesh& mesh, std::vector<int>& label) {
  const int n = static_cast<int>(mesh.V.rows());
  std::vector<int> parent(static_cast<std::size_t>(n));
  std::iota(parent.begin(), parent.end(), 0);
  auto find = [&](int x) {
    while (parent[x] != x) x = parent[x] = parent[parent[x]];
    return x;
  };
  for (Eigen::Index f = 0; f < mesh.F.rows(); ++f)
    for (int k = 0; k < 3; ++k) {
      const int a = find(mesh.F(f, k)), b = find(mesh.F(f, (k + 1) % 3));
      if (a != b) parent[std::max(a, b)] = std::min(a, b);
    }
  label.assign(static_cast<std::size_t>(n), -1);
  int count = 0;
  std::vector<int> id(static_cast<std::size_t>(n), -1);
  for (int i = 0; i < n; ++i) {
    const int r = find(i);
    if (id[r] < 0) id[r] = count++;
    label[i] = id[r];
  }
  return count;
}

}  // namespace virtual_tryon
