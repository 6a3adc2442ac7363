// Cloth-body collision tests behind one interface, so the drape does not care how they are found:
// image space (depth and normal maps, Vassilev et al. 2001 sec. 5) or object space (the body mesh
// through its box tree, the paper's comparison and the accurate mode where the maps see badly).
// Both are built from a Body and cached with it; re-rendering per frame for a moving body would
// only need a new collider.
#pragma once

#include "virtual_tryon/core/body/body.h"
#include "virtual_tryon/core/drape/depth_maps.h"

#include <memory>

namespace virtual_tryon {

enum class CollisionMode { ImageSpace, ObjectSpace };

class BodyCollider {
 public:
  virtual ~BodyCollider() = default;
  // True when p is inside the body or within the tolerance of its surface; `normal` receives the
  // outward body normal to respond along and `depth` how far p lies inside the tolerance shell
  // (metres, >= 0).
  virtual bool collide(const Eigen::Vector3d& p, Eigen::Vector3d& normal, double& depth) const = 0;
};

class ImageSpaceCollider final : public BodyCollider {
 public:
  explicit ImageSpaceCollider(std::shared_ptr<const DepthMaps> maps) : maps_(std::move(maps)) {}
  bool collide(const Eigen::Vector3d& p, Eigen::Vector3d& normal, double& depth) const override {
    return maps_->collide(p, normal, &depth);
  }
  const DepthMaps& maps() const { return *maps_; }

 private:
  std::shared_ptr<const DepthMaps> maps_;
};

// Nearest body point (closestPointOnBody); p collides when its signed distance (by the nearest face's
// normal) is below tol.
class ObjectSpaceCollider final : public BodyCollider {
 public:
  ObjectSpaceCollider(const Body& body, double tol) : body_(body), tol_(tol) {}
  bool collide(const Eigen::Vector3d& p, Eigen::Vector3d& normal, double& depth) const override;

 private:
  const Body& body_;
  double tol_;
};

}  // namespace virtual_tryon
