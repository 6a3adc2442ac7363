#include "virtual_tryon/core/geometry/mesh.h"

#include "core/geometry/wording.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <array>
#include <cmath>
#include <numeric>
#include <sstream>

namespace virtual_tryon {

namespace {

using wording::metres;
using wording::plural;

void fatal(MeshValidation& r, const std::string& message) {
  r.ok = false;
  r.message = message;
}

void joinWarnings(MeshValidation& r) {
  r.message.clear();
  for (const std::string& w : r.warnings) r.message += (r.message.empty() ? "" : "; ") + w;
}

}  // namespace

std::string checkMeshSize(std::uint64_t vertices, std::uint64_t faces, const MeshLimits& limits,
                          const std::string& what) {
  if (vertices > limits.max_vertices)
    return what + " has " + std::to_string(vertices) + " vertices, over the limit of " +
           std::to_string(limits.max_vertices) + " vertices (MeshLimits::max_vertices)";
  if (faces > limits.max_faces)
    return what + " has " + std::to_string(faces) + " triangles, over the limit of " +
           std::to_string(limits.max_faces) + " triangles (MeshLimits::max_faces)";
  return "";
}

namespace {

// The fatal checks of validate(), in order: empty, over the size limits, non-finite coordinates,
// indices out of range. False (with r.ok = false and the message) on the first that fails;
// `used` receives, per vertex, whether a face uses it.
bool usable(const TriMesh& mesh, const std::string& what, const MeshLimits& limits, MeshValidation& r,
            std::vector<char>& used) {
  std::ostringstream msg;
  if (mesh.V.rows() == 0) {
    fatal(r, what + " has no vertices");
    return false;
  }
  if (mesh.F.rows() == 0) {
    fatal(r, what + " has no faces (" + std::to_string(mesh.V.rows()) + " vertices)");
    return false;
  }
  const std::string tooBig = checkMeshSize(static_cast<std::uint64_t>(mesh.V.rows()),
                                           static_cast<std::uint64_t>(mesh.F.rows()), limits, what);
  if (!tooBig.empty()) {
    fatal(r, tooBig);
    return false;
  }
  for (Eigen::Index i = 0; i < mesh.V.rows(); ++i)
    if (!mesh.V.row(i).allFinite()) ++r.non_finite_vertices;
  if (r.non_finite_vertices > 0) {
    msg << what << " has " << r.non_finite_vertices << " vertices with NaN or Inf coordinates";
    fatal(r, msg.str());
    return false;
  }
  const Eigen::Index n = mesh.V.rows();
  used.assign(static_cast<std::size_t>(n), 0);
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
    msg << what << " has " << r.out_of_range_indices << " vertex indices out of range [0, " << n
        << ") (first in face " << firstBad << ")";
    fatal(r, msg.str());
    return false;
  }
  return true;
}

// Degenerate faces: a repeated index, or zero area relative to the scale (the box diagonal).
std::size_t countDegenerateFaces(const TriMesh& mesh, double scale) {
  const double areaTol = 1e-14 * scale * scale;
  std::size_t degenerate = 0;
  for (Eigen::Index f = 0; f < mesh.F.rows(); ++f) {
    const int a = mesh.F(f, 0), b = mesh.F(f, 1), c = mesh.F(f, 2);
    if (a == b || b == c || a == c) {
      ++degenerate;
      continue;
    }
    const Eigen::Vector3d e1 = mesh.V.row(b) - mesh.V.row(a);
    const Eigen::Vector3d e2 = mesh.V.row(c) - mesh.V.row(a);
    if (0.5 * e1.cross(e2).norm() <= areaTol) ++degenerate;
  }
  return degenerate;
}

// Duplicate faces: the same three vertices in any order (a face and its flipped twin too).
std::size_t countDuplicateFaces(const TriMesh& mesh) {
  std::vector<std::array<int, 3>> faces(static_cast<std::size_t>(mesh.F.rows()));
  for (Eigen::Index f = 0; f < mesh.F.rows(); ++f) {
    std::array<int, 3>& t = faces[static_cast<std::size_t>(f)];
    t = {mesh.F(f, 0), mesh.F(f, 1), mesh.F(f, 2)};
    std::sort(t.begin(), t.end());
  }
  std::sort(faces.begin(), faces.end());
  std::size_t duplicates = 0;
  for (std::size_t i = 1; i < faces.size(); ++i) duplicates += faces[i] == faces[i - 1];
  return duplicates;
}

// Duplicate vertices: exactly the same position (not joined, so the mesh is split there).
std::size_t countDuplicateVertices(const TriMesh& mesh) {
  std::vector<Eigen::Index> order(static_cast<std::size_t>(mesh.V.rows()));
  std::iota(order.begin(), order.end(), Eigen::Index(0));
  auto less = [&](Eigen::Index a, Eigen::Index b) {
    for (int k = 0; k < 3; ++k)
      if (mesh.V(a, k) != mesh.V(b, k)) return mesh.V(a, k) < mesh.V(b, k);
    return false;
  };
  std::sort(order.begin(), order.end(), less);
  std::size_t duplicates = 0;
  for (std::size_t i = 1; i < order.size(); ++i)
    duplicates += mesh.V.row(order[i]) == mesh.V.row(order[i - 1]);
  return duplicates;
}

// One sentence per warning that the counts and the extent call for, then the joined message.
void writeWarnings(MeshValidation& r, const std::string& what) {
  if (r.degenerate_faces > 0)
    r.warnings.push_back(what + " has " + plural(r.degenerate_faces, "degenerate face", "degenerate faces") +
                         " (a repeated vertex or zero area)");
  if (r.duplicate_faces > 0)
    r.warnings.push_back(what + " has " + plural(r.duplicate_faces, "duplicate face", "duplicate faces") +
                         " (the same three vertices as another face)");
  if (r.duplicate_vertices > 0)
    r.warnings.push_back(what + " has " +
                         plural(r.duplicate_vertices, "duplicate vertex", "duplicate vertices") +
                         " (the same position as another vertex; faces are not joined there)");
  if (r.unused_vertices > 0)
    r.warnings.push_back(what + " has " + plural(r.unused_vertices, "unused vertex", "unused vertices") +
                         " (in no face)");
  if (r.extent > kMaxPlausibleExtent)
    r.warnings.push_back(what + " is " + metres(r.extent) +
                         " m long (the longest side of its bounding box); " +
                         "coordinates are expected in metres: is it in millimetres?");
  joinWarnings(r);
}

}  // namespace

MeshValidation validate(const TriMesh& mesh, const std::string& what, const MeshLimits& limits) {
  MeshValidation r;
  std::vector<char> used;
  if (!usable(mesh, what, limits, r, used)) return r;
  Eigen::Vector3d lo, hi;
  boundingBox(mesh, lo, hi);
  r.extent = (hi - lo).maxCoeff();
  r.degenerate_faces = countDegenerateFaces(mesh, std::max((hi - lo).norm(), 1e-300));
  if (r.degenerate_faces == static_cast<std::size_t>(mesh.F.rows())) {
    // Nothing to collide with or to move out: no face has an area, so no normal and no inside.
    const std::string faces = r.degenerate_faces == 1 ? "its only face has"
                                                      : "all " + std::to_string(r.degenerate_faces) + " of its faces have";
    fatal(r, what + ": " + faces + " zero area (a repeated vertex or collinear corners)");
    return r;
  }
  r.duplicate_faces = countDuplicateFaces(mesh);
  r.duplicate_vertices = countDuplicateVertices(mesh);
  r.unused_vertices = static_cast<std::size_t>(std::count(used.begin(), used.end(), 0));
  writeWarnings(r, what);
  return r;
}

std::vector<std::string> placementWarnings(const TriMesh& body, const TriMesh& garment) {
  if (body.V.rows() == 0 || garment.V.rows() == 0) return {};
  Eigen::Vector3d blo, bhi, glo, ghi;
  boundingBox(body, blo, bhi);
  boundingBox(garment, glo, ghi);
  return placementWarnings(blo, bhi, glo, ghi);
}

std::vector<std::string> placementWarnings(const Eigen::Vector3d& blo, const Eigen::Vector3d& bhi,
                                           const Eigen::Vector3d& glo, const Eigen::Vector3d& ghi) {
  std::vector<std::string> out;
  if (!blo.allFinite() || !bhi.allFinite() || !glo.allFinite() || !ghi.allFinite()) return out;
  const Eigen::Vector3d gap = (glo - bhi).cwiseMax(blo - ghi).cwiseMax(0.0);
  const double distance = gap.norm();
  const double extent = std::max((bhi - blo).norm(), (ghi - glo).norm());
  if (distance > extent)
    out.push_back("garment is " + metres(distance) + " m away from the body (bounding boxes; body " +
                  metres((bhi - blo).norm()) + " m, garment " + metres((ghi - glo).norm()) +
                  " m across): they cannot touch; are both in the same frame and units?");
  return out;
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

namespace {

// Every face side as ((lo, hi), 3f + k), sorted: bucketed by lo (a counting sort, which keeps the
// sides of each bucket in the order of 3f + k), then each small bucket sorted by hi, stable.
std::vector<std::pair<std::pair<int, int>, Eigen::Index>> sortedFaceSides(const MatrixX3i& F) {
  const Eigen::Index nf = F.rows();
  std::vector<std::pair<std::pair<int, int>, Eigen::Index>> half(static_cast<std::size_t>(3 * nf));
  if (nf == 0) return half;
  auto side = [&F](Eigen::Index f, int k) {
    const int a = F(f, k), b = F(f, (k + 1) % 3);
    return std::make_pair(std::make_pair(std::min(a, b), std::max(a, b)), 3 * f + k);
  };
  const int lowest = F.minCoeff(), highest = F.maxCoeff();
  if (lowest < 0 || static_cast<long long>(highest) - lowest > 16 * static_cast<long long>(half.size()) + 1024) {
    for (Eigen::Index f = 0; f < nf; ++f)  // indices out of a sane range: a plain sort
      for (int k = 0; k < 3; ++k) half[static_cast<std::size_t>(3 * f + k)] = side(f, k);
    std::sort(half.begin(), half.end());
    return half;
  }
  std::vector<int> start(static_cast<std::size_t>(highest - lowest) + 2, 0);
  for (Eigen::Index f = 0; f < nf; ++f)
    for (int k = 0; k < 3; ++k) ++start[static_cast<std::size_t>(side(f, k).first.first - lowest) + 1];
  for (std::size_t i = 1; i < start.size(); ++i) start[i] += start[i - 1];
  std::vector<int> fill(start.begin(), start.end() - 1);
  for (Eigen::Index f = 0; f < nf; ++f)
    for (int k = 0; k < 3; ++k) {
      const auto s = side(f, k);
      half[static_cast<std::size_t>(fill[static_cast<std::size_t>(s.first.first - lowest)]++)] = s;
    }
  for (std::size_t i = 0; i + 1 < start.size(); ++i)
    std::stable_sort(half.begin() + start[i], half.begin() + start[i + 1],
                     [](const auto& x, const auto& y) { return x.first.second < y.first.second; });
  return half;
}

}  // namespace

MatrixX2i uniqueEdges(const TriMesh& mesh, MatrixX3i* faceEdges) {
  const Eigen::Index nf = mesh.F.rows();
  const std::vector<std::pair<std::pair<int, int>, Eigen::Index>> half = sortedFaceSides(mesh.F);
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

std::size_t boundaryLoops(const TriMesh& mesh) {
  MatrixX3i faceEdges;
  const MatrixX2i E = uniqueEdges(mesh, &faceEdges);
  std::vector<int> uses(static_cast<std::size_t>(E.rows()), 0);
  for (Eigen::Index f = 0; f < faceEdges.rows(); ++f)
    for (int k = 0; k < 3; ++k) ++uses[static_cast<std::size_t>(faceEdges(f, k))];
  // Union-find over the vertices of boundary edges; each root that a boundary edge reaches is a loop.
  std::vector<int> parent(static_cast<std::size_t>(mesh.V.rows()));
  for (std::size_t i = 0; i < parent.size(); ++i) parent[i] = static_cast<int>(i);
  auto find = [&](int v) {
    while (parent[v] != v) v = parent[v] = parent[parent[v]];
    return v;
  };
  std::vector<char> onBoundary(parent.size(), 0);
  for (Eigen::Index e = 0; e < E.rows(); ++e) {
    if (uses[static_cast<std::size_t>(e)] != 1) continue;
    const int a = E(e, 0), b = E(e, 1);
    if (a < 0 || b < 0 || a >= mesh.V.rows() || b >= mesh.V.rows()) continue;
    onBoundary[a] = onBoundary[b] = 1;
    parent[find(a)] = find(b);
  }
  std::size_t loops = 0;
  for (std::size_t v = 0; v < parent.size(); ++v)
    if (onBoundary[v] && find(static_cast<int>(v)) == static_cast<int>(v)) ++loops;
  return loops;
}

std::vector<double> vertexEdgeStrain(const TriMesh& rest, const MatrixX3d& V) {
  std::vector<double> strain(static_cast<std::size_t>(rest.V.rows()), 0.0);
  if (V.rows() != rest.V.rows()) return strain;
  const MatrixX2i E = uniqueEdges(rest);
  for (Eigen::Index e = 0; e < E.rows(); ++e) {
    const int a = E(e, 0), b = E(e, 1);
    const double l0 = (rest.V.row(a) - rest.V.row(b)).norm();
    if (!(l0 > 0)) continue;
    const double s = std::abs((V.row(a) - V.row(b)).norm() / l0 - 1.0);
    strain[static_cast<std::size_t>(a)] = std::max(strain[static_cast<std::size_t>(a)], s);
    strain[static_cast<std::size_t>(b)] = std::max(strain[static_cast<std::size_t>(b)], s);
  }
  return strain;
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
  return edgeTopology(FE, E.rows());
}

EdgeTopology edgeTopology(const MatrixX3i& FE, Eigen::Index edges) {
  std::vector<int> count(static_cast<std::size_t>(edges), 0);
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
    v += tripleProduct(a, b, c);
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

void facesRoundVertices(const MatrixX3i& F, int numVertices, std::vector<int>& start, std::vector<int>& faces) {
  start.assign(static_cast<std::size_t>(numVertices) + 1, 0);
  for (Eigen::Index f = 0; f < F.rows(); ++f)
    for (int k = 0; k < 3; ++k) ++start[F(f, k) + 1];
  for (int v = 0; v < numVertices; ++v) start[v + 1] += start[v];
  faces.resize(static_cast<std::size_t>(start[numVertices]));
  std::vector<int> fill(start.begin(), start.end() - 1);
  for (Eigen::Index f = 0; f < F.rows(); ++f)
    for (int k = 0; k < 3; ++k) faces[fill[F(f, k)]++] = static_cast<int>(f);
}

}  // namespace virtual_tryon
