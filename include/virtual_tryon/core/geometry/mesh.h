// Triangle meshes as plain matrices (libigl style): V is #V by 3 (metres), F is #F by 3
// (0-based vertex indices, counter-clockwise seen from the front side, so that
// (v1 - v0) x (v2 - v0) points along the outward normal of a body).
#pragma once

#include <Eigen/Core>

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace virtual_tryon {

using MatrixX3d = Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor>;
using MatrixX3i = Eigen::Matrix<int, Eigen::Dynamic, 3, Eigen::RowMajor>;
using MatrixX2i = Eigen::Matrix<int, Eigen::Dynamic, 2, Eigen::RowMajor>;

struct TriMesh {
  MatrixX3d V;  // #V by 3 vertex positions
  MatrixX3i F;  // #F by 3 triangle indices into V

  Eigen::Index numVertices() const { return V.rows(); }
  Eigen::Index numFaces() const { return F.rows(); }
  bool empty() const { return V.rows() == 0 || F.rows() == 0; }
};

// Size limits for meshes that come from outside (files, messages, patterns). Readers and
// converters check the declared sizes (a PLY header, a cloud's width * height, polygon counts)
// against them before allocating anything proportional to those sizes, so a hostile or broken
// input is refused with a message instead of exhausting memory.
struct MeshLimits {
  std::size_t max_vertices = 2000000;  // vertices of one mesh (cloth nodes of one meshed pattern)
  std::size_t max_faces = 4000000;     // triangles of one mesh, after fan triangulation
};

// "N vertices, over the limit of M (MeshLimits::max_vertices)" and likewise for faces; "" when
// within the limits. `what` names the mesh. Only counts: nothing is allocated.
std::string checkMeshSize(std::uint64_t vertices, std::uint64_t faces, const MeshLimits& limits,
                          const std::string& what = "mesh");

// What validate() found. `ok` is false when the mesh cannot be used at all (empty, over the size
// limits, non-finite coordinates, indices out of range; for a body, validateBody, also inside out);
// degenerate and duplicate faces, duplicate and unused vertices, and a size that suggests
// millimetres are warnings: counted and described in `warnings`, and the mesh stays usable.
struct MeshValidation {
  bool ok = true;
  std::string message;  // the fatal problem, or the warnings joined by "; " ("" when clean)
  std::vector<std::string> warnings;  // one sentence each, naming the mesh
  std::size_t non_finite_vertices = 0;
  std::size_t out_of_range_indices = 0;
  std::size_t degenerate_faces = 0;  // repeated index or zero area (relative to the mesh scale)
  std::size_t duplicate_faces = 0;   // same three vertices as an earlier face (any order)
  std::size_t duplicate_vertices = 0;  // exactly the same position as an earlier vertex
  std::size_t unused_vertices = 0;
  double extent = 0;  // longest side of the bounding box, metres
};

// Above this longest bounding-box side (metres) a mesh gets a units warning: a person or a garment
// is a couple of metres, so a 1700 m body was most likely written in millimetres.
constexpr double kMaxPlausibleExtent = 10.0;

// Checks a mesh. `what` names it in the message ("body", "garment"). What a body needs beyond
// this (topology, pieces, orientation) is checked by prepareBody and validateBody
// (body/body_preparation.h).
MeshValidation validate(const TriMesh& mesh, const std::string& what = "mesh",
                        const MeshLimits& limits = MeshLimits());

// Warnings about a body and a garment together: their bounding boxes far apart (more than the
// larger of the two extents between them: nothing will touch). Empty when none.
std::vector<std::string> placementWarnings(const TriMesh& body, const TriMesh& garment);
// The same from the two bounding boxes (body min, max; garment min, max).
std::vector<std::string> placementWarnings(const Eigen::Vector3d& bodyMin, const Eigen::Vector3d& bodyMax,
                                           const Eigen::Vector3d& garmentMin,
                                           const Eigen::Vector3d& garmentMax);

// Unit face normals, #F by 3; a degenerate face gets (0, 0, 0).
MatrixX3d faceNormals(const TriMesh& mesh);

// Area-weighted unit vertex normals, #V by 3.
MatrixX3d vertexNormals(const TriMesh& mesh);

// The faces round each vertex, as offsets: the faces of vertex v are faces[start[v] ..
// start[v + 1]), in increasing order. `numVertices` >= every index in F (libigl's
// vertex_triangle_adjacency, flattened).
void facesRoundVertices(const MatrixX3i& F, int numVertices, std::vector<int>& start, std::vector<int>& faces);

// Unique undirected edges, #E by 2 with E(e,0) < E(e,1), sorted. If faceEdges is given it
// receives #F by 3: faceEdges(f,k) is the index of the edge from corner k to corner (k+1)%3.
MatrixX2i uniqueEdges(const TriMesh& mesh, MatrixX3i* faceEdges = nullptr);

// Per vertex, the largest edge strain |l / l0 - 1| of the edges at it: l0 from `rest`, l from `V`
// (#V by 3, the same vertex order and faces as rest). #V values; 0 where no edge of non-zero rest
// length meets the vertex. The fit map of a garment against its input (render/fit_render.h).
std::vector<double> vertexEdgeStrain(const TriMesh& rest, const MatrixX3d& V);

// Mean length of the unique edges (0 for an empty mesh).
double meanEdgeLength(const TriMesh& mesh);

// Number of boundary edges (edges with exactly one incident face) and non-manifold edges
// (more than two incident faces).
struct EdgeTopology {
  std::size_t boundary_edges = 0;
  std::size_t non_manifold_edges = 0;
  bool closed() const { return boundary_edges == 0 && non_manifold_edges == 0; }
};
EdgeTopology edgeTopology(const TriMesh& mesh);
// The same from uniqueEdges' face-edge table (#F by 3, into `edges` edges) of the mesh.
EdgeTopology edgeTopology(const MatrixX3i& faceEdges, Eigen::Index edges);

// Boundary loops: the connected pieces of the graph of boundary edges (edges with exactly one
// incident face). A disc has 1, a tube 2, a closed surface 0; two holes that share a vertex count
// as one.
std::size_t boundaryLoops(const TriMesh& mesh);

// Signed volume enclosed by the mesh (positive for a closed, outward-oriented mesh).
double signedVolume(const TriMesh& mesh);
// u x v, by the formula of Eigen's cross() (the same values to the bit), always inlined: Eigen's
// cross of two difference expressions is a call of its own in the detection's inner loops.
inline Eigen::Vector3d crossProduct(const Eigen::Vector3d& u, const Eigen::Vector3d& v) {
  return Eigen::Vector3d(u.y() * v.z() - u.z() * v.y(), u.z() * v.x() - u.x() * v.z(), u.x() * v.y() - u.y() * v.x());
}
// a . (b x c), written out (six times the signed volume of the tetrahedron (0, a, b, c)); what
// signedVolume sums over the faces, in face order.
inline double tripleProduct(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& c) {
  return a.x() * (b.y() * c.z() - b.z() * c.y()) + a.y() * (b.z() * c.x() - b.x() * c.z()) +
         a.z() * (b.x() * c.y() - b.y() * c.x());
}

// Axis-aligned bounds: min and max corner.
void boundingBox(const TriMesh& mesh, Eigen::Vector3d& lo, Eigen::Vector3d& hi);

// Connected components over shared vertices: #V labels in 0..count-1; returns count.
int connectedComponents(const TriMesh& mesh, std::vector<int>& label);

}  // namespace virtual_tryon
