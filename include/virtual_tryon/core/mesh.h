// Triangle meshes as plain matrices (libigl style): V is #V by 3 (metres), F is #F by 3
// (0-based vertex indices, counter-clockwise seen from the front side, so that
// (v1 - v0) x (v2 - v0) points along the outward normal of a body).
#pragma once

#include <Eigen/Core>

#include <cstddef>
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

// What validate() found. `ok` is false when the mesh cannot be used at all (empty, non-finite
// coordinates, indices out of range); degenerate faces are counted but do not make it unusable.
struct MeshValidation {
  bool ok = true;
  std::string message;  // first fatal problem, or a summary of the warnings
  std::size_t non_finite_vertices = 0;
  std::size_t out_of_range_indices = 0;
  std::size_t degenerate_faces = 0;  // repeated index or zero area (relative to the mesh scale)
  std::size_t unused_vertices = 0;
};

// Checks a mesh. `what` names it in the message ("body", "garment").
MeshValidation validate(const TriMesh& mesh, const std::string& what = "mesh");

// Unit face normals, #F by 3; a degenerate face gets (0, 0, 0).
MatrixX3d faceNormals(const TriMesh& mesh);

// Area-weighted unit vertex normals, #V by 3.
MatrixX3d vertexNormals(const TriMesh& mesh);

// Unique undirected edges, #E by 2 with E(e,0) < E(e,1), sorted. If faceEdges is given it
// receives #F by 3: faceEdges(f,k) is the index of the edge from corner k to corner (k+1)%3.
MatrixX2i uniqueEdges(const TriMesh& mesh, MatrixX3i* faceEdges = nullptr);

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

// Signed volume enclosed by the mesh (positive for a closed, outward-oriented mesh).
double signedVolume(const TriMesh& mesh);

// Axis-aligned bounds: min and max corner.
void boundingBox(const TriMesh& mesh, Eigen::Vector3d& lo, Eigen::Vector3d& hi);

// Connected components over shared vertices: #V labels in 0..count-1; returns count.
int connectedComponents(const TriMesh& mesh, std::vector<int>& label);

}  // namespace virtual_tryon
