#include "virtual_tryon/core/body/body.h"

#include "core/geometry/fcl_bvh.h"


#include <chrono>
#include <stdexcept>
#include <string>
#include <thread>

namespace virtual_tryon {

Body::Body(TriMesh mesh) : mesh_(std::move(mesh)) {
  face_normals_ = virtual_tryon::faceNormals(mesh_);
  buildAdjacency();  // the edge list, which the topology is counted over
  topology_ = edgeTopology(face_edges_, edges_.rows());
  signed_volume_ = virtual_tryon::signedVolume(mesh_);
  boundingBox(mesh_, box_min_, box_max_);
}

// A frame's geometry from its vertices: face normals and the signed volume in one pass over the
// faces (the sums of faceNormals and signedVolume, in the same order: the same values to the bit),
// the face normals written in place (a stream of frames hands over the buffer of the frame before),
// then the bounds. Edge and vertex normals are computed when asked for (edgeNormal, vertexNormal).
void Body::computeFrameGeometry() {
  const MatrixX3d& V = mesh_.V;
  const MatrixX3i& F = mesh_.F;
  face_normals_.resize(F.rows(), 3);
  double volume = 0;
  for (Eigen::Index f = 0; f < F.rows(); ++f) {
    const Eigen::Vector3d a = V.row(F(f, 0)), b = V.row(F(f, 1)), c = V.row(F(f, 2));
    volume += a.dot(b.cross(c));
    const Eigen::Vector3d n = (b - a).cross(c - a);
    const double len = n.norm();
    face_normals_.row(f) = len > 0 ? Eigen::Vector3d(n / len) : Eigen::Vector3d::Zero();
  }
  signed_volume_ = volume / 6.0;
  boundingBox(mesh_, box_min_, box_max_);
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

// Joins a thread when the scope it was started in ends, however that ends (before anything the
// thread reads goes away).
struct JoinOnExit {
  std::thread& t;
  ~JoinOnExit() {
    if (t.joinable()) t.join();
  }
};

}  // namespace

Body::Body(const Body& previous, MatrixX3d V) : mesh_{std::move(V), previous.mesh_.F} {
  checkFrameSize(previous.mesh_.V.rows(), mesh_.V.rows());
  topology_ = previous.topology_;
  // previous's lists (built now if they were not) and a copy of its trees
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
  face_normals_ = std::move(previous.face_normals_);  // a buffer of the same size, written over
  adoptFrame(std::move(previous.edges_), std::move(previous.face_edges_), std::move(previous.vertex_face_start_),
             std::move(previous.vertex_faces_), previous.bvh_built_ ? std::move(previous.bvh_) : nullptr);
  previous.bvh_built_ = false;
  previous.adjacency_built_ = false;
}

// The shared part of both frame constructors: the frame's own geometry over the lists of the
// frame before, and its trees (when it had them) refitted to this frame's vertices. FCL's tree is
// refitted on a thread of their own while this one computes the face normals and then refits the
// detection's box tree (about equal halves; both only read the vertices and faces, each writes its
// own tree; the thread is joined before the trees are used, however this returns).
void Body::adoptFrame(MatrixX2i edges, MatrixX3i faceEdges, std::vector<int> vertexFaceStart,
                      std::vector<int> vertexFaces, std::unique_ptr<BodyBVH> trees) {
  double treeSeconds = 0;
  std::thread refit;
  if (trees)
    refit = std::thread([this, &trees, &treeSeconds] {
      const auto t0 = std::chrono::steady_clock::now();
      trees->refitFcl(mesh_);
      treeSeconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    });
  JoinOnExit join{refit};
  std::call_once(adjacency_once_, [&] {
    edges_ = std::move(edges);
    face_edges_ = std::move(faceEdges);
    if (edge_first_face_.size() != static_cast<std::size_t>(edges_.rows())) computeEdgeFirstFaces();
    adjacency_built_ = true;
  });
  std::call_once(vertex_adjacency_once_, [&] {
    vertex_face_start_ = std::move(vertexFaceStart);
    vertex_faces_ = std::move(vertexFaces);
  });
  computeFrameGeometry();
  if (!trees) return;
  const auto t0 = std::chrono::steady_clock::now();
  trees->refitFaceTree(mesh_);  // FCL's tree is the other thread's
  const double boxSeconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  refit.join();
  treeSeconds += boxSeconds;
  std::call_once(bvh_once_, [&] {
    bvh_ = std::move(trees);
    bvh_seconds_ = treeSeconds;
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
    if (mesh_.F(f, 0) == b || mesh_.F(f, 1) == b || mesh_.F(f, 2) == b) sum += face_normals_.row(f).transpose();
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

void Body::buildAdjacency() const {
  std::call_once(adjacency_once_, [this] {
    edges_ = uniqueEdges(mesh_, &face_edges_);
    computeEdgeFirstFaces();
    adjacency_built_ = true;
  });
}

std::unique_ptr<BodyBVH> BodyBVH::copy() const {
  auto out = std::make_unique<BodyBVH>();
  out->model = std::make_shared<FclModel>(*model);
  if (tree_) {
    auto tree = std::make_unique<FaceBoxTree>(*tree_);
    std::call_once(out->tree_once_, [&] { out->tree_ = std::move(tree); });
  }
  return out;
}

namespace {

// FCL's tree refitted bottom-up in one pass over its node array (a node's children come after it:
// recursiveBuildTree gives them the next free indices), each leaf to its triangle's current
// vertices. FCL's own update (beginUpdateModel .. endUpdateModel) fits each leaf around the
// previous and the current vertices (a swept box, for continuous collision) through a recursion
// and out-of-line accessors, about 1.5 ms on a 26,756-face body; the ray-parity test needs this
// frame's boxes alone. FCL's vertex array is kept current too.
void refitFclTree(FclModel& model, const MatrixX3d& V, const MatrixX3i& F) {
  for (Eigen::Index i = 0; i < V.rows(); ++i) model.vertices[i] = V.row(i).transpose();
  for (int id = model.getNumBVs() - 1; id >= 0; --id) {
    fcl::BVNode<fcl::AABBd>& node = model.getBV(id);
    if (node.isLeaf()) {
      const int f = node.primitiveId();
      const Eigen::Vector3d a = V.row(F(f, 0)), b = V.row(F(f, 1)), c = V.row(F(f, 2));
      node.bv.min_ = a.cwiseMin(b).cwiseMin(c);
      node.bv.max_ = a.cwiseMax(b).cwiseMax(c);
    } else {
      const fcl::AABBd& l = model.getBV(node.leftChild()).bv;
      const fcl::AABBd& r = model.getBV(node.rightChild()).bv;
      node.bv.min_ = l.min_.cwiseMin(r.min_);
      node.bv.max_ = l.max_.cwiseMax(r.max_);
    }
  }
}

}  // namespace

void BodyBVH::refitFcl(const TriMesh& mesh) { refitFclTree(*model, mesh.V, mesh.F); }

void BodyBVH::refitFaceTree(const TriMesh& mesh) {
  if (tree_) tree_->refit(mesh.V, mesh.F);
}

void Body::buildVertexAdjacency() const {
  std::call_once(vertex_adjacency_once_, [this] {
    facesRoundVertices(mesh_.F, static_cast<int>(mesh_.V.rows()), vertex_face_start_, vertex_faces_);
  });
}

Body::~Body() = default;

const BodyBVH& Body::bvh() const {
  std::call_once(bvh_once_, [this] {
    const auto t0 = std::chrono::steady_clock::now();
    auto b = std::make_unique<BodyBVH>();
    // The detection's box tree (counted with the BVH) on a thread of its own while FCL builds its
    // tree here: both only read the mesh (on body_hm08, 26,756 faces: 30-38 ms -> about 20).
    std::thread faceTree([&b, this] { b->faceTree(mesh_); });
    JoinOnExit join{faceTree};
    b->model = buildFclModel(mesh_.V, mesh_.F, nullptr);
    faceTree.join();
    bvh_ = std::move(b);
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
