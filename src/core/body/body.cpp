#include "virtual_tryon/core/body/body.h"

#include "core/geometry/body_bvh.h"

#include <chrono>
#include <stdexcept>
#include <string>

namespace virtual_tryon {

Body::Body(TriMesh mesh) : mesh_(std::move(mesh)) {
  buildAdjacency();  // the edge list, which the topology is counted over
  topology_ = edgeTopology(face_edges_, edges_.rows());
  signed_volume_ = virtual_tryon::signedVolume(mesh_);
  boundingBox(mesh_, box_min_, box_max_);
}

// A frame's geometry from its vertices: the signed volume (signedVolume's sum, in the same order:
// the same value to the bit) and the bounds. Face, edge and vertex normals are computed when asked
// for (faceNormal, edgeNormal, vertexNormal).
void Body::computeFrameGeometry() {
  signed_volume_ = virtual_tryon::signedVolume(mesh_);
  boundingBox(mesh_, box_min_, box_max_);
}

// As faceNormals of mesh.h computes it, for one face.
Eigen::Vector3d Body::faceNormal(int f) const {
  const Eigen::Vector3d a = mesh_.V.row(mesh_.F(f, 0));
  const Eigen::Vector3d n =
      (Eigen::Vector3d(mesh_.V.row(mesh_.F(f, 1))) - a).cross(Eigen::Vector3d(mesh_.V.row(mesh_.F(f, 2))) - a);
  const double len = n.norm();
  return len > 0 ? Eigen::Vector3d(n / len) : Eigen::Vector3d::Zero();
}

const MatrixX3d& Body::faceNormals() const {
  std::call_once(face_normals_once_, [this] { face_normals_ = virtual_tryon::faceNormals(mesh_); });
  return face_normals_;
}

// Over the edge list (the same list, in the same order, as meanEdgeLength's uniqueEdges gives: the
// same mean), on the first call.
double Body::meanEdgeLength() const {
  std::call_once(mean_edge_once_, [this] {
    const MatrixX2i& E = edges();
    double sum = 0;
    for (Eigen::Index e = 0; e < E.rows(); ++e) sum += (mesh_.V.row(E(e, 0)) - mesh_.V.row(E(e, 1))).norm();
    mean_edge_length_ = E.rows() ? sum / static_cast<double>(E.rows()) : 0.0;
  });
  return mean_edge_length_;
}

namespace {

void checkFrameSize(Eigen::Index previous, Eigen::Index now) {
  if (now != previous)
    throw std::invalid_argument("a new frame of a body needs its " + std::to_string(previous) + " vertices, got " +
                                std::to_string(now));
}

}  // namespace

Body::Body(const Body& previous, MatrixX3d V) : mesh_{std::move(V), previous.mesh_.F} {
  checkFrameSize(previous.mesh_.V.rows(), mesh_.V.rows());
  topology_ = previous.topology_;
  // previous's lists (built now if they were not) and a copy of its tree
  edge_first_face_ = previous.edgeFirstFaces();
  adoptFrame(previous.edges(), previous.faceEdges(), previous.vertexFaceStart(), previous.vertexFaces(),
             previous.bvh_built_ ? previous.bvh_->copy() : nullptr);
}

Body::Body(Body&& previous, MatrixX3d V) {
  checkFrameSize(previous.mesh_.V.rows(), V.rows());
  previous.buildAdjacency();
  previous.buildVertexAdjacency();
  mesh_.F = std::move(previous.mesh_.F);
  mesh_.V = std::move(V);
  topology_ = std::move(previous.topology_);
  edge_first_face_ = std::move(previous.edge_first_face_);
  adoptFrame(std::move(previous.edges_), std::move(previous.face_edges_), std::move(previous.vertex_face_start_),
             std::move(previous.vertex_faces_), previous.bvh_built_ ? std::move(previous.bvh_) : nullptr);
  previous.bvh_built_ = false;
  previous.adjacency_built_ = false;
  previous.vertex_adjacency_built_ = false;
}

// The shared part of both frame constructors: the frame's own geometry over the lists of the
// frame before, and its tree (when it had one) refitted to this frame's vertices.
void Body::adoptFrame(MatrixX2i edges, MatrixX3i faceEdges, std::vector<int> vertexFaceStart,
                      std::vector<int> vertexFaces, std::unique_ptr<BodyBVH> tree) {
  std::call_once(adjacency_once_, [&] {
    edges_ = std::move(edges);
    face_edges_ = std::move(faceEdges);
    if (edge_first_face_.size() != static_cast<std::size_t>(edges_.rows())) computeEdgeFirstFaces();
    adjacency_built_ = true;
  });
  std::call_once(vertex_adjacency_once_, [&] {
    vertex_face_start_ = std::move(vertexFaceStart);
    vertex_faces_ = std::move(vertexFaces);
    vertex_adjacency_built_ = true;
  });
  if (!tree) {
    computeFrameGeometry();
    return;
  }
  // The volume summed in the refit's pass over the faces (signedVolume's sum, in its order).
  const auto t0 = std::chrono::steady_clock::now();
  double volume = 0;
  tree->refit(mesh_, [&](const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& c) {
    volume += tripleProduct(a, b, c);
  });
  signed_volume_ = volume / 6.0;
  boundingBox(mesh_, box_min_, box_max_);
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  std::call_once(bvh_once_, [&] {
    bvh_ = std::move(tree);
    bvh_seconds_ = seconds;
    bvh_built_ = true;
    bvh_refitted_ = true;
  });
}

namespace {

Eigen::Vector3d unitOrZero(const Eigen::Vector3d& s) {
  const double len = s.norm();
  return len > 0 ? Eigen::Vector3d(s / len) : s;
}

}  // namespace

// The faces round the edge's first end that have its second end too are the faces incident to
// it, in increasing order (facesRoundVertices): the sum a pass over the faces would take.
Eigen::Vector3d Body::edgeNormal(int e) const {
  buildVertexAdjacency();
  const MatrixX2i& E = edges();
  const int a = E(e, 0), b = E(e, 1);
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  for (int i = vertex_face_start_[a]; i < vertex_face_start_[a + 1]; ++i) {
    const int f = vertex_faces_[static_cast<std::size_t>(i)];
    if (mesh_.F(f, 0) == b || mesh_.F(f, 1) == b || mesh_.F(f, 2) == b) sum += faceNormal(f);
  }
  return unitOrZero(sum);
}

Eigen::Vector3d Body::vertexNormal(int v) const {
  buildVertexAdjacency();
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  for (int i = vertex_face_start_[v]; i < vertex_face_start_[v + 1]; ++i) {
    const int f = vertex_faces_[static_cast<std::size_t>(i)];
    const Eigen::Vector3d a = mesh_.V.row(mesh_.F(f, 0));
    sum += (Eigen::Vector3d(mesh_.V.row(mesh_.F(f, 1))) - a).cross(Eigen::Vector3d(mesh_.V.row(mesh_.F(f, 2))) - a);
  }
  return unitOrZero(sum);
}

const MatrixX3d& Body::edgeNormals() const {
  std::call_once(edge_normals_once_, [this] {
    const Eigen::Index n = edges().rows();
    edge_normals_.resize(n, 3);
    for (Eigen::Index e = 0; e < n; ++e) edge_normals_.row(e) = edgeNormal(static_cast<int>(e)).transpose();
  });
  return edge_normals_;
}

const MatrixX3d& Body::vertexNormals() const {
  std::call_once(vertex_normals_once_, [this] {
    vertex_normals_.resize(mesh_.V.rows(), 3);
    for (Eigen::Index v = 0; v < mesh_.V.rows(); ++v)
      vertex_normals_.row(v) = vertexNormal(static_cast<int>(v)).transpose();
  });
  return vertex_normals_;
}

void Body::computeEdgeFirstFaces() const {
  edge_first_face_.assign(static_cast<std::size_t>(edges_.rows()), -1);
  for (Eigen::Index f = 0; f < face_edges_.rows(); ++f)
    for (int k = 0; k < 3; ++k) {
      int& first = edge_first_face_[static_cast<std::size_t>(face_edges_(f, k))];
      if (first < 0) first = static_cast<int>(f);
    }
}

// Both build once (std::call_once); once built, a flag read answers without call_once's own cost
// (a thread-local lookup in a shared library), which the detection pays per garment face.
void Body::buildAdjacency() const {
  if (adjacency_built_.load(std::memory_order_acquire)) return;
  std::call_once(adjacency_once_, [this] {
    edges_ = uniqueEdges(mesh_, &face_edges_);
    computeEdgeFirstFaces();
    adjacency_built_ = true;
  });
}

void Body::buildVertexAdjacency() const {
  if (vertex_adjacency_built_.load(std::memory_order_acquire)) return;
  std::call_once(vertex_adjacency_once_, [this] {
    facesRoundVertices(mesh_.F, static_cast<int>(mesh_.V.rows()), vertex_face_start_, vertex_faces_);
    vertex_adjacency_built_ = true;
  });
}

Body::~Body() = default;

const BodyBVH& Body::bvh() const {
  std::call_once(bvh_once_, [this] {
    const auto t0 = std::chrono::steady_clock::now();
    bvh_ = std::make_unique<BodyBVH>(mesh_);
    bvh_seconds_ = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    bvh_built_ = true;
  });
  return *bvh_;
}

std::shared_ptr<const DepthMaps> Body::depthMaps(const CollisionParams& params) const {
  std::lock_guard<std::mutex> lock(maps_mutex_);
  if (!maps_ || maps_tol_ != params.tol || maps_size_ != params.map_size) {
    maps_ = std::make_shared<const DepthMaps>(mesh_, params);
    maps_tol_ = params.tol;
    maps_size_ = params.map_size;
    ++maps_renders_;
  }
  return maps_;
}

int Body::depthMapRenders() const {
  std::lock_guard<std::mutex> lock(maps_mutex_);
  return maps_renders_;
}

}  // namespace virtual_tryon
