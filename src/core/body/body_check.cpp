#include "virtual_tryon/core/body/body_check.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <sstream>
#include <utility>
#include <vector>

namespace virtual_tryon {

namespace {

struct PieceStats {
  bool open_or_nonmanifold = false;
  bool inconsistent = false;
  double signed_volume = 0;    // from the piece's box centre
  double absolute_volume = 0;  // sum of |tetrahedron volumes| from the same centre
  int state = 0;               // +1 outward, -1 inverted, 0 unclear
};

BodyCheck analyse(const TriMesh& mesh, const BodyCheckParams& params, std::vector<int>& faceLabel,
                  std::vector<PieceStats>& pieces) {
  BodyCheck r;
  r.vertices = static_cast<std::size_t>(mesh.V.rows());
  r.faces = static_cast<std::size_t>(mesh.F.rows());
  const MeshValidation v = validate(mesh, "body", params.limits);
  if (!v.ok) {
    r.ok = false;
    r.message = v.message;
    r.summary = "unusable: " + v.message;
    return r;
  }
  if (!(params.open_flip_ratio > 0 && params.open_flip_ratio <= 1)) {
    r.ok = false;
    r.message = "open_flip_ratio must be in (0, 1], got " + std::to_string(params.open_flip_ratio);
    r.summary = "unusable: " + r.message;
    return r;
  }
  r.ok = true;
  r.degenerate_faces = v.degenerate_faces;
  r.unused_vertices = v.unused_vertices;
  const EdgeTopology topo = edgeTopology(mesh);
  r.boundary_edges = topo.boundary_edges;
  r.non_manifold_edges = topo.non_manifold_edges;
  r.closed = topo.closed();

  // Pieces: connected components over shared vertices, numbered among the used vertices only.
  std::vector<int> vertexLabel;
  const int labels = connectedComponents(mesh, vertexLabel);
  std::vector<int> pieceOf(static_cast<std::size_t>(labels), -1);
  const Eigen::Index nf = mesh.F.rows();
  faceLabel.assign(static_cast<std::size_t>(nf), -1);
  int count = 0;
  for (Eigen::Index f = 0; f < nf; ++f) {
    int& p = pieceOf[static_cast<std::size_t>(vertexLabel[static_cast<std::size_t>(mesh.F(f, 0))])];
    if (p < 0) p = count++;
    faceLabel[static_cast<std::size_t>(f)] = p;
  }
  r.pieces = static_cast<std::size_t>(count);
  pieces.assign(static_cast<std::size_t>(count), PieceStats());

  // Directed half-edges grouped by undirected edge: boundary, non-manifold and inconsistently
  // wound edges per piece.
  struct Half {
    int lo, hi;
    bool forward;  // traversed lo -> hi
    int piece;
    bool operator<(const Half& o) const { return lo != o.lo ? lo < o.lo : hi < o.hi; }
  };
  std::vector<Half> half;
  half.reserve(static_cast<std::size_t>(3 * nf));
  for (Eigen::Index f = 0; f < nf; ++f)
    for (int k = 0; k < 3; ++k) {
      const int a = mesh.F(f, k), b = mesh.F(f, (k + 1) % 3);
      half.push_back({std::min(a, b), std::max(a, b), a < b, faceLabel[static_cast<std::size_t>(f)]});
    }
  std::sort(half.begin(), half.end());
  for (std::size_t i = 0; i < half.size();) {
    std::size_t j = i + 1;
    while (j < half.size() && half[j].lo == half[i].lo && half[j].hi == half[i].hi) ++j;
    PieceStats& ps = pieces[static_cast<std::size_t>(half[i].piece)];
    if (j - i != 2) {
      ps.open_or_nonmanifold = true;
    } else if (half[i].forward == half[i + 1].forward) {
      ps.inconsistent = true;
      ++r.inconsistent_edges;
    }
    i = j;
  }

  // Volumes per piece, each from the centre of its bounding box (exact for a closed, consistently
  // wound piece whatever the centre; the centre makes the hint of an open piece translation-free).
  std::vector<Eigen::Vector3d> lo(pieces.size(), Eigen::Vector3d::Constant(INFINITY));
  std::vector<Eigen::Vector3d> hi(pieces.size(), Eigen::Vector3d::Constant(-INFINITY));
  for (Eigen::Index f = 0; f < nf; ++f) {
    const std::size_t p = static_cast<std::size_t>(faceLabel[static_cast<std::size_t>(f)]);
    for (int k = 0; k < 3; ++k) {
      const Eigen::Vector3d x = mesh.V.row(mesh.F(f, k));
      lo[p] = lo[p].cwiseMin(x);
      hi[p] = hi[p].cwiseMax(x);
    }
  }
  for (Eigen::Index f = 0; f < nf; ++f) {
    const std::size_t p = static_cast<std::size_t>(faceLabel[static_cast<std::size_t>(f)]);
    const Eigen::Vector3d c = 0.5 * (lo[p] + hi[p]);
    const Eigen::Vector3d a = Eigen::Vector3d(mesh.V.row(mesh.F(f, 0))) - c;
    const Eigen::Vector3d b = Eigen::Vector3d(mesh.V.row(mesh.F(f, 1))) - c;
    const Eigen::Vector3d d = Eigen::Vector3d(mesh.V.row(mesh.F(f, 2))) - c;
    const double t = a.dot(b.cross(d)) / 6.0;
    pieces[p].signed_volume += t;
    pieces[p].absolute_volume += std::abs(t);
  }
  for (PieceStats& ps : pieces) {
    r.signed_volume += ps.signed_volume;
    if (!ps.open_or_nonmanifold && !ps.inconsistent) {
      // Exact sign; a zero volume (all faces flat) stays unclear.
      const double tiny = 1e-12 * ps.absolute_volume;
      ps.state = ps.signed_volume > tiny ? 1 : (ps.signed_volume < -tiny ? -1 : 0);
    } else {
      const double limit = params.open_flip_ratio * ps.absolute_volume;
      ps.state = ps.absolute_volume > 0 && ps.signed_volume >= limit
                     ? 1
                     : (ps.absolute_volume > 0 && ps.signed_volume <= -limit ? -1 : 0);
    }
    if (ps.state < 0) ++r.inverted_pieces;
    if (ps.state == 0) ++r.unclear_pieces;
  }
  r.orientation = r.inverted_pieces > 0                ? BodyOrientation::Inverted
                  : r.unclear_pieces < pieces.size() ? BodyOrientation::Outward
                                                     : BodyOrientation::Unclear;
  return r;
}

void writeSummary(BodyCheck& r) {
  if (!r.ok) return;
  std::ostringstream s;
  s.precision(3);
  s << (r.closed ? "closed" : "open") << ", " << r.pieces << (r.pieces == 1 ? " piece, " : " pieces, ")
    << r.boundary_edges << " boundary edges, " << r.non_manifold_edges << " non-manifold edges, ";
  if (r.inconsistent_edges > 0) s << r.inconsistent_edges << " inconsistently wound edges, ";
  s << r.degenerate_faces << " degenerate faces, volume " << r.signed_volume << " m^3";
  if (!r.closed || r.inconsistent_edges > 0) s << " (a hint only)";
  s << ", ";
  if (r.flipped)
    s << "inverted: flipped" << (r.pieces > 1 ? " (" + std::to_string(r.flipped_faces) + " faces)" : "");
  else if (r.orientation == BodyOrientation::Inverted)
    s << "inverted";
  else if (r.orientation == BodyOrientation::Outward)
    s << "outward";
  else
    s << "orientation unclear";
  if (r.unclear_pieces > 0 && r.unclear_pieces < r.pieces)
    s << ", " << r.unclear_pieces << " pieces unclear";
  r.summary = s.str();
}

double since(const std::chrono::steady_clock::time_point& t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

}  // namespace

void flipFaces(TriMesh& mesh) { mesh.F.col(1).swap(mesh.F.col(2)); }

BodyCheck checkBody(const TriMesh& mesh, const BodyCheckParams& params) {
  const auto t0 = std::chrono::steady_clock::now();
  std::vector<int> faceLabel;
  std::vector<PieceStats> pieces;
  BodyCheck r = analyse(mesh, params, faceLabel, pieces);
  writeSummary(r);
  r.seconds = since(t0);
  return r;
}

BodyCheck orientBody(TriMesh& mesh, const BodyCheckParams& params) {
  const auto t0 = std::chrono::steady_clock::now();
  std::vector<int> faceLabel;
  std::vector<PieceStats> pieces;
  BodyCheck r = analyse(mesh, params, faceLabel, pieces);
  if (r.ok && r.inverted_pieces > 0) {
    for (Eigen::Index f = 0; f < mesh.F.rows(); ++f)
      if (pieces[static_cast<std::size_t>(faceLabel[static_cast<std::size_t>(f)])].state < 0) {
        std::swap(mesh.F(f, 1), mesh.F(f, 2));
        ++r.flipped_faces;
      }
    r.flipped = true;
    // Reversing a piece negates its tetrahedra: the volume and orientation after flipping.
    r.signed_volume = 0;
    for (PieceStats& ps : pieces) {
      if (ps.state < 0) {
        ps.signed_volume = -ps.signed_volume;
        ps.state = 1;
      }
      r.signed_volume += ps.signed_volume;
    }
    r.orientation = BodyOrientation::Outward;
  }
  writeSummary(r);
  r.seconds = since(t0);
  return r;
}

}  // namespace virtual_tryon
