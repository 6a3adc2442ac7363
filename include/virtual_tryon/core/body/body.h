// A rigid, outward-oriented body and the data derived from it. Derived data is built lazily, once,
// on first use, and is safe to share between threads (std::call_once): a body that is reused for
// many garments pays for its BVH once.
#pragma once

#include "virtual_tryon/core/drape/depth_maps.h"
#include "virtual_tryon/core/geometry/mesh.h"

#include <atomic>
#include <memory>
#include <mutex>
#include <vector>

namespace virtual_tryon {

// The body's face tree, one box tree for every body query: edge-face detection, nearest point,
// ray-parity inside test (core/geometry/body_bvh.h).
class BodyBVH;

class Body {
 public:
  explicit Body(TriMesh mesh);
  // A new frame of `previous`'s body (a body that moves): the same faces, new vertex positions V
  // (#V by 3, as many as previous has; else std::invalid_argument). What depends on the faces alone
  // is reused (edge topology, the edge list, the faces round each vertex: built on previous first if
  // it had not built them); bounds and volume are computed for V (face, edge and vertex normals and
  // the mean edge length when asked for); previous's face tree, when built, is
  // copied and refitted to V (same tree, new boxes: bvhRefitted()), not rebuilt. Depth maps are
  // not carried over (the body moved).
  Body(const Body& previous, MatrixX3d V);
  // The same, taking previous's lists and tree instead of copying them (previous is left empty:
  // only to be destroyed or assigned). What a stream of frames uses.
  Body(Body&& previous, MatrixX3d V);
  ~Body();
  Body(const Body&) = delete;
  Body& operator=(const Body&) = delete;

  const TriMesh& mesh() const { return mesh_; }
  // Face f's unit outward normal (zero for a degenerate face), computed on the call; faceNormals():
  // all of them (#F by 3, the same values), computed on the first call (thread-safe). A moving
  // body asks for the few faces its crossings and contacts need.
  Eigen::Vector3d faceNormal(int f) const;
  const MatrixX3d& faceNormals() const;
  // Edge adjacency, built with the body (its topology is counted over the edge list) and reused by
  // every frame of it.
  const MatrixX2i& edges() const { buildAdjacency(); return edges_; }             // #E by 2 unique edges
  const MatrixX3i& faceEdges() const { buildAdjacency(); return face_edges_; }    // #F by 3 into edges()
  // Unit mean of the normals of the faces incident to edge e (outward direction at a ridge or a
  // valley), computed on the call; edgeNormals(): all of them (#E by 3), computed on the first call
  // (thread-safe). A moving body asks for the few edges its crossings need.
  Eigen::Vector3d edgeNormal(int e) const;
  const MatrixX3d& edgeNormals() const;
  // Per edge: the lowest-numbered face that has it (a detection tests each edge from that face
  // alone, where both of its faces are visited).
  const std::vector<int>& edgeFirstFaces() const { buildAdjacency(); return edge_first_face_; }
  bool adjacencyBuilt() const { return adjacency_built_; }
  // The faces round each vertex (vertex v: vertexFaces()[vertexFaceStart()[v] ..
  // vertexFaceStart()[v + 1]), facesRoundVertices of mesh.h), built on the first call to either
  // (thread-safe), then reused.
  const std::vector<int>& vertexFaceStart() const { buildVertexAdjacency(); return vertex_face_start_; }
  const std::vector<int>& vertexFaces() const { buildVertexAdjacency(); return vertex_faces_; }
  // Vertex v's unit normal (area-weighted, as mesh.h vertexNormals), computed on the call;
  // vertexNormals(): all of them (#V by 3), computed on the first call (thread-safe).
  Eigen::Vector3d vertexNormal(int v) const;
  const MatrixX3d& vertexNormals() const;
  const EdgeTopology& topology() const { return topology_; }
  bool closed() const { return topology_.closed(); }
  double meanEdgeLength() const;  // over edges(), computed on the first call (thread-safe)
  // Signed enclosed volume (mesh.h signedVolume), m^3: negative for a closed body wound inside out.
  double signedVolume() const { return signed_volume_; }
  const Eigen::Vector3d& boxMin() const { return box_min_; }  // axis-aligned bounds
  const Eigen::Vector3d& boxMax() const { return box_max_; }

  // The face tree; built on the first call (thread-safe), then reused.
  const BodyBVH& bvh() const;
  bool bvhBuilt() const { return bvh_built_; }
  bool bvhRefitted() const { return bvh_refitted_; }  // refitted from a previous frame's tree
  double bvhBuildSeconds() const { return bvh_seconds_; }

  // Front/back depth and normal maps for image-space collisions, rendered on the first call for
  // these (tol, map_size) and cached: the same parameters again cost nothing; other parameters
  // render new maps (the last set is kept). Thread-safe.
  std::shared_ptr<const DepthMaps> depthMaps(const CollisionParams& params) const;
  int depthMapRenders() const;  // how many times maps were rendered for this body

 private:
  void buildAdjacency() const;
  void buildVertexAdjacency() const;
  void computeEdgeFirstFaces() const;
  void computeFrameGeometry();
  void adoptFrame(MatrixX2i edges, MatrixX3i faceEdges, std::vector<int> vertexFaceStart,
                  std::vector<int> vertexFaces, std::unique_ptr<BodyBVH> tree);

  TriMesh mesh_;
  mutable std::once_flag face_normals_once_;
  mutable MatrixX3d face_normals_;
  mutable std::once_flag adjacency_once_;
  mutable std::atomic<bool> adjacency_built_{false};
  mutable MatrixX2i edges_;
  mutable MatrixX3i face_edges_;
  mutable std::once_flag edge_normals_once_;
  mutable MatrixX3d edge_normals_;
  mutable std::vector<int> edge_first_face_;
  mutable std::once_flag vertex_adjacency_once_;
  mutable std::atomic<bool> vertex_adjacency_built_{false};
  mutable std::vector<int> vertex_face_start_, vertex_faces_;
  mutable std::once_flag vertex_normals_once_;
  mutable MatrixX3d vertex_normals_;
  EdgeTopology topology_;
  mutable std::once_flag mean_edge_once_;
  mutable double mean_edge_length_ = 0;
  double signed_volume_ = 0;
  Eigen::Vector3d box_min_{0, 0, 0}, box_max_{0, 0, 0};

  mutable std::once_flag bvh_once_;
  mutable std::unique_ptr<BodyBVH> bvh_;
  mutable std::atomic<bool> bvh_built_{false};
  mutable double bvh_seconds_ = 0;
  bool bvh_refitted_ = false;

  mutable std::mutex maps_mutex_;
  mutable std::shared_ptr<const DepthMaps> maps_;
  mutable double maps_tol_ = -1;
  mutable int maps_size_ = -1;
  mutable int maps_renders_ = 0;
};

}  // namespace virtual_tryon
