// The drape's velocity response to collisions (Vassilev et al. 2001 sec. 6, eq. 12), shared by the
// drape on a still body (drape.cpp) and the garment worn on a moving one (worn_garment.cpp).
#pragma once

#include "virtual_tryon/core/drape/cloth.h"
#include "virtual_tryon/core/drape/depth_maps.h"

#include <vector>

namespace virtual_tryon {

// A still body's collider (ImageSpaceCollider, ObjectSpaceCollider) as CollisionResponse reads
// one: its surface does not move (velocity 0).
template <class Still>
struct StillBody {
  const Still& body;
  bool collide(const Eigen::Vector3d& p, Eigen::Vector3d& normal, double& depth, Eigen::Vector3d& velocity) const {
    velocity.setZero();
    return body.collide(p, normal, depth);
  }
};

// eq. 12 on the velocity relative to the body's surface, which moves at `surface` (m/s; for
// example speed n when only its speed along the outward normal n is known): v - surface is
// reflected and rubbed, then surface is added back. So a surface moving out pushes what touches
// it (a moving arm pushes the sleeve), friction drags the cloth along with the skin under it, and
// at rest this is the paper's response.
inline Eigen::Vector3d movingCollisionResponse(const Eigen::Vector3d& v, const Eigen::Vector3d& n,
                                               const Eigen::Vector3d& surface, double friction, double reflection) {
  if (surface.isZero(0)) return collisionResponse(v, n, friction, reflection);
  return collisionResponse(v - surface, n, friction, reflection) + surface;
}

// Velocity response of every colliding node and quad midpoint; a node that gets several
// responses gets their mean (sec. 6). Templated on the (final) collider so the per-point test
// inlines; the collider is held by value (a small view of the body, collider() to change it
// between steps).
template <class Collider>
class CollisionResponse {
 public:
  CollisionResponse(Collider collider, const CollisionParams& p, bool quads, const ClothState& cloth,
                    double dt, double pushOut)
      : collider_(collider), p_(p), quads_(quads), cloth_(cloth), dt_(dt), push_out_(pushOut) {}

  Collider& collider() { return collider_; }
  void setTimeStep(double dt) { dt_ = dt; }
  // Nodes that collided in the last call (quad midpoints not counted).
  std::size_t collidingNodes() const { return colliding_; }

  void operator()(const MatrixX3d& x, MatrixX3d& v) {
    const Eigen::Index n = x.rows();
    // Only the nodes a response reaches are written (a few hundred of thousands): the sums and
    // counts are zero between calls, and the nodes touched are listed to be averaged and reset.
    if (sum_.rows() != n) {
      sum_.setZero(n, 3);
      count_.assign(static_cast<std::size_t>(n), 0);
    }
    touched_.clear();
    colliding_ = 0;
    Eigen::Vector3d normal, surface;
    double depth = 0;
    for (Eigen::Index i = 0; i < n; ++i) {
      if (!collider_.collide(x.row(i).transpose(), normal, depth, surface)) continue;
      Eigen::Vector3d r = movingCollisionResponse(v.row(i).transpose(), normal, surface, p_.friction, p_.reflection);
      // Beyond the paper: a node deeper than the shell also gets back a fraction of its depth per
      // step, so points the velocity response alone leaves inside come out (bounded: at most
      // push_out * depth / dt).
      if (depth > p_.tol && dt_ > 0) r += (push_out_ * (depth - p_.tol) / dt_) * normal;
      add(i, r.transpose());
      ++colliding_;
    }
    if (quads_)
      for (const auto& q : cloth_.quads()) {
        const Eigen::Vector3d mid = 0.25 * (x.row(q[0]) + x.row(q[1]) + x.row(q[2]) + x.row(q[3])).transpose();
        if (!collider_.collide(mid, normal, depth, surface)) continue;
        const Eigen::Vector3d vm = 0.25 * (v.row(q[0]) + v.row(q[1]) + v.row(q[2]) + v.row(q[3])).transpose();
        const Eigen::RowVector3d r =
            movingCollisionResponse(vm, normal, surface, p_.friction, p_.reflection).transpose();
        for (int c : q) add(c, r);
      }
    for (const Eigen::Index i : touched_) {
      v.row(i) = sum_.row(i) / count_[static_cast<std::size_t>(i)];
      sum_.row(i).setZero();
      count_[static_cast<std::size_t>(i)] = 0;
    }
  }

 private:
  void add(Eigen::Index i, const Eigen::RowVector3d& r) {
    if (count_[static_cast<std::size_t>(i)]++ == 0) touched_.push_back(i);
    sum_.row(i) += r;
  }

  Collider collider_;
  CollisionParams p_;
  bool quads_;
  const ClothState& cloth_;
  double dt_, push_out_;
  MatrixX3d sum_;
  std::vector<int> count_;
  std::vector<Eigen::Index> touched_;  // nodes with count_ > 0, in the order first reached
  std::size_t colliding_ = 0;
};

}  // namespace virtual_tryon
