#include "virtual_tryon/core/body/body_check.h"

#include "core/body/body_analysis.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <sstream>
#include <utility>
#include <vector>

namespace virtual_tryon {

namespace body_analysis {
namespace {

// Pieces: connected components over shared vertices, numbered among the used vertices only.
void labelPieces(const TriMesh& mesh, BodyAnalysis& a) {
  std::vector<int> vertexLabel;
  const int labels = connectedComponents(mesh, vertexLabel);
  a.component_piece.assign(static_cast<std::size_t>(labels), -1);
  const Eigen::Index nf = mesh.F.rows();
  a.face_piece.assign(static_cast<std::size_t>(nf), -1);
  int count = 0;
  for (Eigen::Index f = 0; f < nf; ++f) {
    int& p = a.component_piece[static_cast<std::size_t>(vertexLabel[static_cast<std::size_t>(mesh.F(f, 0))])];
    if (p < 0) p = count++;
    a.face_piece[static_cast<std::size_t>(f)] = p;
  }
  a.check.pieces = static_cast<std::size_t>(count);
  a.pieces.assign(static_cast<std::size_t>(count), PieceStats());
}

// Directed half-edges grouped by undirected edge: boundary (one face), non-manifold (more than two)
// and inconsistently wound edges, in total and per piece.
void countEdges(const TriMesh& mesh, BodyAnalysis& a) {
  struct Half {
    int lo, hi;
    bool forward;  // traversed lo -> hi
    int piece;
    bool operator<(const Half& o) const { return lo != o.lo ? lo < o.lo : hi < o.hi; }
  };
  const Eigen::Index nf = mesh.F.rows();
  std::vector<Half> half;
  half.reserve(static_cast<std::size_t>(3 * nf));
  for (Eigen::Index f = 0; f < nf; ++f)
    for (int k = 0; k < 3; ++k) {
      const int u = mesh.F(f, k), v = mesh.F(f, (k + 1) % 3);
      half.push_back({std::min(u, v), std::max(u, v), u < v, a.face_piece[static_cast<std::size_t>(f)]});
    }
  std::sort(half.begin(), half.end());
  BodyCheck& r = a.check;
  for (std::size_t i = 0; i < half.size();) {
    std::size_t j = i + 1;
    while (j < half.size() && half[j].lo == half[i].lo && half[j].hi == half[i].hi) ++j;
    PieceStats& ps = a.pieces[static_cast<std::size_t>(half[i].piece)];
    if (j - i != 2) {
      ps.open_or_nonmanifold = true;
      if (j - i == 1) ++r.boundary_edges;
      else ++r.non_manifold_edges;
    } else if (half[i].forward == half[i + 1].forward) {
      ps.inconsistent = true;
      ++r.inconsistent_edges;
    }
    i = j;
  }
  r.closed = r.boundary_edges == 0 && r.non_manifold_edges == 0;
}

// Volumes per piece, each from the centre of its bounding box (exact for a closed, consistently
// wound piece whatever the centre; the centre makes the hint of an open piece translation-free),
// and from the origin.
void measureVolumes(const TriMesh& mesh, BodyAnalysis& a) {
  const Eigen::Index nf = mesh.F.rows();
  std::vector<Eigen::Vector3d> lo(a.pieces.size(), Eigen::Vector3d::Constant(INFINITY));
  std::vector<Eigen::Vector3d> hi(a.pieces.size(), Eigen::Vector3d::Constant(-INFINITY));
  for (Eigen::Index f = 0; f < nf; ++f) {
    const std::size_t p = static_cast<std::size_t>(a.face_piece[static_cast<std::size_t>(f)]);
    for (int k = 0; k < 3; ++k) {
      const Eigen::Vector3d x = mesh.V.row(mesh.F(f, k));
      lo[p] = lo[p].cwiseMin(x);
      hi[p] = hi[p].cwiseMax(x);
    }
  }
  for (Eigen::Index f = 0; f < nf; ++f) {
    const std::size_t p = static_cast<std::size_t>(a.face_piece[static_cast<std::size_t>(f)]);
    PieceStats& ps = a.pieces[p];
    const Eigen::Vector3d x0 = mesh.V.row(mesh.F(f, 0)), x1 = mesh.V.row(mesh.F(f, 1)),
                          x2 = mesh.V.row(mesh.F(f, 2));
    ps.origin_volume += x0.dot(x1.cross(x2)) / 6.0;
    const Eigen::Vector3d c = 0.5 * (lo[p] + hi[p]);
    const Eigen::Vector3d u = x0 - c, v = x1 - c, w = x2 - c;
    const double t = u.dot(v.cross(w)) / 6.0;
    ps.signed_volume += t;
    ps.absolute_volume += std::abs(t);
  }
}

// The orientation of each piece (see body_check.h) and of the whole.
void classifyPieces(const BodyCheckParams& params, BodyAnalysis& a) {
  BodyCheck& r = a.check;
  for (PieceStats& ps : a.pieces) {
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
  r.orientation = r.inverted_pieces > 0                  ? BodyOrientation::Inverted
                  : r.unclear_pieces < a.pieces.size() ? BodyOrientation::Outward
                                                       : BodyOrientation::Unclear;
}

}  // namespace

BodyAnalysis analyse(const TriMesh& mesh, const MeshValidation& validation, const BodyCheckParams& params) {
  BodyAnalysis a;
  BodyCheck& r = a.check;
  r.vertices = static_cast<std::size_t>(mesh.V.rows());
  r.faces = static_cast<std::size_t>(mesh.F.rows());
  if (!validation.ok) {
    r.ok = false;
    r.message = validation.message;
    r.summary = "unusable: " + validation.message;
    return a;
  }
  if (!(params.open_flip_ratio > 0 && params.open_flip_ratio <= 1)) {
    r.ok = false;
    r.message = "open_flip_ratio must be in (0, 1], got " + std::to_string(params.open_flip_ratio);
    r.summary = "unusable: " + r.message;
    return a;
  }
  r.ok = true;
  r.degenerate_faces = validation.degenerate_faces;
  r.unused_vertices = validation.unused_vertices;
  labelPieces(mesh, a);
  countEdges(mesh, a);
  measureVolumes(mesh, a);
  classifyPieces(params, a);
  return a;
}

void flipInvertedPieces(TriMesh& mesh, BodyAnalysis& a) {
  BodyCheck& r = a.check;
  if (!r.ok || r.inverted_pieces == 0) return;
  for (Eigen::Index f = 0; f < mesh.F.rows(); ++f)
    if (a.pieces[static_cast<std::size_t>(a.face_piece[static_cast<std::size_t>(f)])].state < 0) {
      std::swap(mesh.F(f, 1), mesh.F(f, 2));
      ++r.flipped_faces;
    }
  r.flipped = true;
  // Reversing a piece negates its tetrahedra: the volume and orientation after flipping.
  r.signed_volume = 0;
  for (PieceStats& ps : a.pieces) {
    if (ps.state < 0) {
      ps.signed_volume = -ps.signed_volume;
      ps.origin_volume = -ps.origin_volume;
      ps.state = 1;
    }
    r.signed_volume += ps.signed_volume;
  }
  r.orientation = BodyOrientation::Outward;
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

}  // namespace body_analysis

namespace {

double since(const std::chrono::steady_clock::time_point& t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

}  // namespace

void flipFaces(TriMesh& mesh) { mesh.F.col(1).swap(mesh.F.col(2)); }

BodyCheck checkBody(const TriMesh& mesh, const BodyCheckParams& params) {
  const auto t0 = std::chrono::steady_clock::now();
  body_analysis::BodyAnalysis a = body_analysis::analyse(mesh, validate(mesh, "body", params.limits), params);
  body_analysis::writeSummary(a.check);
  a.check.seconds = since(t0);
  return a.check;
}

BodyCheck orientBody(TriMesh& mesh, const BodyCheckParams& params) {
  const auto t0 = std::chrono::steady_clock::now();
  body_analysis::BodyAnalysis a = body_analysis::analyse(mesh, validate(mesh, "body", params.limits), params);
  body_analysis::flipInvertedPieces(mesh, a);
  body_analysis::writeSummary(a.check);
  a.check.seconds = since(t0);
  return a.check;
}

}  // namespace virtual_tryon
