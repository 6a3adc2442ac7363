// Internal to the core: FCL's types stay in the files that use them.
#pragma once

#include "virtual_tryon/core/geometry/mesh.h"

#include "core/geometry/face_box_tree.h"

#include <fcl/geometry/bvh/BVH_model.h>
#include <fcl/narrowphase/collision_object.h>

#include <algorithm>
#include <memory>
#include <mutex>
#include <vector>

namespace virtual_tryon {

// FCL's AABB tree of the body serves the ray-parity inside test (point_queries.cpp); the
// edge-face detection and nearest-point queries use the core's own box tree (face_box_tree.h).
using FclModel = fcl::BVHModel<fcl::AABBd>;

class BodyBVH {
 public:
  std::shared_ptr<FclModel> model;

  // The box tree of the edge-face detection (face_box_tree.h), built on first use.
  const FaceBoxTree& faceTree(const TriMesh& mesh) const;

  // A copy of these trees (body.cpp).
  std::unique_ptr<BodyBVH> copy() const;
  // These trees refitted in place to the same faces on new vertex positions (not while anyone
  // queries them): FCL's and the box tree apart (two threads may do one each).
  void refitFcl(const TriMesh& mesh);
  void refitFaceTree(const TriMesh& mesh);

 private:
  mutable std::once_flag tree_once_;
  mutable std::unique_ptr<FaceBoxTree> tree_;
};

// A BVH over the triangles F (all of them, or only `faces`) of the vertices V.
// Triangle i of the model is F(i) or F(faces[i]). With `faces`, only the vertices those faces use
// go into the model (renumbered), so a BVH over a few faces costs little whatever #V.
inline std::shared_ptr<FclModel> buildFclModel(const MatrixX3d& V, const MatrixX3i& F,
                                               const std::vector<int>* faces) {
  auto model = std::make_shared<FclModel>();
  std::vector<fcl::Vector3d> pts;
  std::vector<fcl::Triangle> tris;
  if (faces) {
    std::vector<int> used;
    used.reserve(3 * faces->size());
    for (int f : *faces)
      for (int k = 0; k < 3; ++k) used.push_back(F(f, k));
    std::sort(used.begin(), used.end());
    used.erase(std::unique(used.begin(), used.end()), used.end());
    pts.reserve(used.size());
    for (int v : used) pts.emplace_back(V.row(v).transpose());
    auto local = [&](int v) {
      return static_cast<std::size_t>(std::lower_bound(used.begin(), used.end(), v) - used.begin());
    };
    tris.reserve(faces->size());
    for (int f : *faces) tris.emplace_back(local(F(f, 0)), local(F(f, 1)), local(F(f, 2)));
  } else {
    pts.resize(static_cast<std::size_t>(V.rows()));
    for (Eigen::Index i = 0; i < V.rows(); ++i) pts[static_cast<std::size_t>(i)] = V.row(i).transpose();
    tris.reserve(static_cast<std::size_t>(F.rows()));
    for (Eigen::Index f = 0; f < F.rows(); ++f) tris.emplace_back(F(f, 0), F(f, 1), F(f, 2));
  }
  // Split at the middle of each node's box (FCL's default takes the mean of its triangles' centres,
  // a pass over them per node: on body_hm08's 26,756 faces about a quarter of the build).
  model->bv_splitter.reset(new fcl::detail::BVSplitter<fcl::AABBd>(fcl::detail::SPLIT_METHOD_BV_CENTER));
  model->beginModel(static_cast<int>(tris.size()), static_cast<int>(pts.size()));
  model->addSubModel(pts, tris);
  model->endModel();
  return model;
}

}  // namespace virtual_tryon
