// The body's box tree (every body query walks it) against answers that share none of its code:
// FCL's distance query (FCL's own OBBRSS tree and sphere-triangle distance) for the nearest point,
// and the ray parity counted over every face, without a tree, for the inside test. On the
// procedural body at rest and on a frame of it swayed by the two-bone skinning, whose tree is
// refitted rather than built.
#include "virtual_tryon/core/body/body.h"
#include "virtual_tryon/core/geometry/edge_face_crossing.h"
#include "virtual_tryon/core/geometry/point_queries.h"
#include "virtual_tryon/core/scenes/procedural_animation.h"

#include <fcl/geometry/bvh/BVH_model.h>
#include <fcl/geometry/shape/sphere.h>
#include <fcl/narrowphase/distance.h>

#include <gtest/gtest.h>

#include <memory>
#include <random>
#include <vector>

using namespace virtual_tryon;

namespace {

// FCL's distance from p to the mesh's surface: a sphere of radius r at p against FCL's tree of
// the triangles, plus r.
class FclDistance {
 public:
  explicit FclDistance(const TriMesh& mesh) {
    auto model = std::make_shared<fcl::BVHModel<fcl::OBBRSSd>>();
    std::vector<fcl::Vector3d> points;
    for (Eigen::Index i = 0; i < mesh.V.rows(); ++i) points.emplace_back(mesh.V.row(i).transpose());
    std::vector<fcl::Triangle> triangles;
    for (Eigen::Index f = 0; f < mesh.F.rows(); ++f) triangles.emplace_back(mesh.F(f, 0), mesh.F(f, 1), mesh.F(f, 2));
    model->beginModel();
    model->addSubModel(points, triangles);
    model->endModel();
    mesh_ = std::make_unique<fcl::CollisionObjectd>(model);
  }
  double operator()(const Eigen::Vector3d& p) const {
    fcl::CollisionObjectd sphere(std::make_shared<fcl::Sphered>(kRadius));
    sphere.setTranslation(p);
    fcl::DistanceRequestd request;
    fcl::DistanceResultd result;
    fcl::distance(mesh_.get(), &sphere, request, result);
    return result.min_distance + kRadius;
  }

 private:
  static constexpr double kRadius = 1e-6;
  std::unique_ptr<fcl::CollisionObjectd> mesh_;
};

// pointInsideBody's rule (three fixed directions, inside when at least two rays cross the surface
// an odd number of times), each ray tested against every face.
bool insideByEveryFace(const TriMesh& mesh, const Eigen::Vector3d& p) {
  Eigen::Vector3d lo, hi;
  boundingBox(mesh, lo, hi);
  if ((p.array() < lo.array()).any() || (p.array() > hi.array()).any()) return false;
  const double length = 4.0 * (hi - lo).norm() + 1.0;
  const Eigen::Vector3d directions[3] = {Eigen::Vector3d(0.5773, 0.5774, 0.5775).normalized(),
                                         Eigen::Vector3d(-0.7071, 0.0123, 0.7069).normalized(),
                                         Eigen::Vector3d(0.0311, -0.9993, -0.0209).normalized()};
  int votes = 0;
  for (const Eigen::Vector3d& d : directions) {
    const Eigen::Vector3d q = p + length * d;
    int hits = 0;
    for (Eigen::Index f = 0; f < mesh.F.rows(); ++f) {
      const Eigen::Vector3d a = mesh.V.row(mesh.F(f, 0)), b = mesh.V.row(mesh.F(f, 1)), c = mesh.V.row(mesh.F(f, 2));
      if (segmentCrossesTriangle(p, q, a, b, c) || segmentCrossesTriangle(q, p, a, b, c)) ++hits;
    }
    votes += hits & 1;
  }
  return votes >= 2;
}

// Points over the body's box and points just off its surface (both sides), where a box of the
// tree that missed its face would show first.
std::vector<Eigen::Vector3d> probes(const Body& body, unsigned seed) {
  std::vector<Eigen::Vector3d> out;
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  const Eigen::Vector3d c = 0.5 * (body.boxMin() + body.boxMax()), h = 0.6 * (body.boxMax() - body.boxMin());
  for (int k = 0; k < 40; ++k) out.push_back(c + Eigen::Vector3d(u(rng), u(rng), u(rng)).cwiseProduct(h));
  const MatrixX3d& V = body.mesh().V;
  for (Eigen::Index v = 0; v < V.rows(); v += std::max<Eigen::Index>(1, V.rows() / 20))
    for (double off : {-3e-3, 3e-3}) out.push_back(V.row(v).transpose() + off * body.vertexNormal(static_cast<int>(v)));
  return out;
}

void expectQueriesAgree(const Body& body, unsigned seed) {
  const FclDistance fcl(body.mesh());
  int inside = 0;
  for (const Eigen::Vector3d& p : probes(body, seed)) {
    const ClosestPoint cp = closestPointOnBody(body, p);
    EXPECT_NEAR(cp.distance, fcl(p), 1e-7) << p.transpose();
    EXPECT_NEAR((cp.point - p).norm(), cp.distance, 1e-12);
    const bool in = pointInsideBody(body, p);
    EXPECT_EQ(in, insideByEveryFace(body.mesh(), p)) << p.transpose();
    inside += in;
  }
  EXPECT_GT(inside, 15);  // the probes reach both sides
}

}  // namespace

TEST(BodyQueries, TheTreeAnswersAsFclAndEveryFaceDo) {
  ProceduralAnimationParams params;
  params.frames = 8;
  const ProceduralAnimation anim = makeProceduralAnimation(params);
  const Body rest(anim.body);
  expectQueriesAgree(rest, 3);
  const Body swayed(rest, anim.body_frames.back());  // the rest body's tree, refitted
  ASSERT_TRUE(swayed.bvhRefitted());
  EXPECT_GT((anim.body_frames.back() - anim.body.V).rowwise().norm().maxCoeff(), 0.02);
  expectQueriesAgree(swayed, 4);
}
