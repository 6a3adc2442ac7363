// Client-side test of tryon_node's ~drape service (started by drape_service.test): a bag of two
// wrapped panels sewn round the top of a capsule, judged by the core's independent brute-force
// counter (reference_check.h); the latched markers; a dt above the stability bound; the depth map
// cache; bad patterns; pattern frames through tf. Tests run in the order written: the first one
// needs a node that has not received a body on its topic.
#include "virtual_tryon/core/geometry/mesh.h"
#include "virtual_tryon/core/drape/pattern.h"
#include "virtual_tryon/core/scenes/procedural.h"
#include "virtual_tryon/core/scenes/procedural_body.h"
#include "virtual_tryon/testing/reference_bvh.h"
#include "virtual_tryon/testing/reference_check.h"
#include "virtual_tryon/ros/conversions.h"
#include <virtual_tryon/Drape.h>
#include "virtual_tryon/ros/pattern_conversions.h"

#include "fixtures.h"
#include "marker_wait.h"

#include <gtest/gtest.h>

#include <pcl_msgs/PolygonMesh.h>
#include <ros/ros.h>
#include <tf2_ros/static_transform_broadcaster.h>
#include <visualization_msgs/MarkerArray.h>

#include <Eigen/Geometry>

#include <cmath>
#include <fstream>
#include <sstream>
#include <mutex>
#include <string>

namespace vt = virtual_tryon;
using vt::Drape;

using virtual_tryon_test::bag;
using virtual_tryon_test::callService;
using virtual_tryon_test::capsule;
using virtual_tryon_test::contains;
using virtual_tryon_test::meshFromMsg;
using virtual_tryon_test::patternMsg;
using virtual_tryon_test::retryWhile;
using virtual_tryon_test::sendStaticTransform;
using virtual_tryon_test::toMsg;

namespace {

const std::string kService = "/tryon_node/drape";
constexpr double kSpacing = 0.03;  // 2 x 200 quads: quick

Drape::Request request(const pcl_msgs::PolygonMesh& body, const vt::GarmentPattern& pattern) {
  Drape::Request req;
  req.body = body;
  req.pattern = pattern;
  req.spacing = kSpacing;
  return req;
}

// Calls the service; gtest failures when it is not there or the call itself fails.
Drape::Response call(const Drape::Request& req) {
  Drape srv;
  srv.request = req;
  return callService(kService, srv);
}

vt::TriMesh returnedGarment(const Drape::Response& res) { return meshFromMsg(res.garment); }

// The bag is sewn, settled on the cap, and crosses nothing (by the independent referee).
void expectDraped(const Drape::Response& res) {
  ASSERT_TRUE(res.success) << res.message;
  EXPECT_TRUE(res.report.converged) << res.report.message;
  EXPECT_GT(res.report.iterations, 0u);
  EXPECT_GT(res.report.sew_iterations, 0u);
  EXPECT_EQ(res.report.seams_total, 3u);
  EXPECT_EQ(res.report.seams_open, 0u);
  EXPECT_EQ(res.report.collision_mode, "image");
  EXPECT_GT(res.report.map_size, 0u);
  EXPECT_GT(res.report.dt, 0.0);
  EXPECT_LE(res.report.dt, res.report.dt_bound);
  EXPECT_TRUE(res.report.resolver_run);
  EXPECT_TRUE(res.report.resolver.converged) << res.report.resolver.reason;
  EXPECT_EQ(res.report.penetrating_after, 0u);
  EXPECT_EQ(res.garment.header.frame_id, "body");
  const vt::TriMesh g = returnedGarment(res);
  EXPECT_EQ(static_cast<std::size_t>(g.numVertices()), res.report.vertices);
  EXPECT_EQ(static_cast<std::size_t>(g.numFaces()), res.report.triangles);
  EXPECT_GT(g.numFaces(), 500);
  const double top = g.V.col(1).maxCoeff();
  EXPECT_GT(top, 0.45) << "the bag should rest on the cap (top of the capsule at y = 0.45)";
  EXPECT_LT(top, 0.50);
  const vt::ReferenceCounts ref = vt::referenceCounts(capsule(), g);
  EXPECT_EQ(ref.garment_edge_crossings, 0u);
  EXPECT_EQ(ref.body_edge_crossings, 0u);
  EXPECT_EQ(ref.vertices_inside, 0u) << "deepest " << ref.max_depth << " m";
}

// ---------------------------------------------------------------------------------------------
// Must run first: nothing has been published on ~body_mesh yet.
TEST(DrapeService, EmptyBodyWithoutTopicDataFails) {
  const Drape::Response res = call(request(pcl_msgs::PolygonMesh(), patternMsg(bag(), "body")));
  EXPECT_FALSE(res.success);
  EXPECT_TRUE(contains(res.message, "no body")) << res.message;
  EXPECT_TRUE(contains(res.message, "body_mesh")) << res.message;
  EXPECT_TRUE(res.garment.polygons.empty());
}

TEST(DrapeService, DrapesTheBagOnTheCapsuleAndPublishesMarkers) {
  const Drape::Response res = call(request(toMsg(capsule(), "body"), patternMsg(bag(), "body")));
  expectDraped(res);
  EXPECT_TRUE(contains(res.message, "depth maps rendered")) << res.message;
  const vt::TriMesh g = returnedGarment(res);

  // Latched markers: the body and the draped garment.
  const virtual_tryon_test::NodeMarkers markers = virtual_tryon_test::waitForNodeMarkers();
  ASSERT_TRUE(markers.received) << "no MarkerArray on /tryon_node/markers within 10 s";
  const visualization_msgs::Marker *body = markers.body(), *garment = markers.garment();
  ASSERT_NE(body, nullptr);
  ASSERT_NE(garment, nullptr);
  EXPECT_EQ(garment->action, visualization_msgs::Marker::ADD);
  EXPECT_EQ(garment->header.frame_id, "body");
  EXPECT_EQ(body->points.size(), 3u * static_cast<std::size_t>(capsule().numFaces()));
  ASSERT_EQ(garment->points.size(), 3u * static_cast<std::size_t>(g.numFaces()));
  const auto& p = garment->points[0];
  EXPECT_LT((Eigen::Vector3d(p.x, p.y, p.z) - Eigen::Vector3d(g.V.row(g.F(0, 0)).transpose())).norm(), 1e-5);
}

TEST(DrapeService, DtAboveTheBoundFailsAndTheNodeKeepsServingFromTheCachedMaps) {
  Drape::Request req = request(toMsg(capsule(), "body"), patternMsg(bag(), "body"));
  req.dt = 0.5;  // the bound is about 2 ms at this spacing
  Drape::Response res = call(req);
  EXPECT_FALSE(res.success);
  EXPECT_TRUE(contains(res.message, "bound")) << res.message;
  EXPECT_TRUE(contains(res.message, "0.5")) << res.message;
  EXPECT_TRUE(res.garment.polygons.empty());
  EXPECT_GT(res.report.dt_bound, 0.0);
  EXPECT_LT(res.report.dt_bound, 0.5);

  // The next request is served; the same body was draped before, so its depth maps come from the
  // cache inside the node's Body (Body::depthMapRenders() did not grow).
  req.dt = 0;
  res = call(req);
  expectDraped(res);
  EXPECT_TRUE(contains(res.message, "depth maps reused")) << res.message;

  // Request values override the parameters; an invalid one is refused by the core's check.
  req.max_iterations = 30;
  req.skip_resolve = true;
  res = call(req);
  EXPECT_TRUE(res.success) << res.message;
  EXPECT_FALSE(res.report.converged);
  EXPECT_EQ(res.report.iterations, 30u);
  EXPECT_FALSE(res.report.resolver_run);
  req = request(toMsg(capsule(), "body"), patternMsg(bag(), "body"));
  req.spacing = -0.03;
  res = call(req);
  EXPECT_FALSE(res.success);
  EXPECT_TRUE(contains(res.message, "spacing")) << res.message;
  req.spacing = kSpacing;
  req.collision_mode = "mesh";
  res = call(req);
  EXPECT_FALSE(res.success);
  EXPECT_TRUE(contains(res.message, "collision_mode 'mesh'")) << res.message;
}

TEST(DrapeService, BadPatternsFailWithAReason) {
  vt::GarmentPattern pattern = patternMsg(bag(), "body");
  pattern.panels[1].outline_u.push_back(0.1);
  Drape::Response res = call(request(toMsg(capsule(), "body"), pattern));
  EXPECT_FALSE(res.success);
  EXPECT_TRUE(contains(res.message, "panel 'back' (index 1)")) << res.message;
  EXPECT_TRUE(contains(res.message, "outline_v")) << res.message;

  pattern = patternMsg(bag(), "body");
  pattern.panels[0].pose.orientation = geometry_msgs::Quaternion();  // all zero
  res = call(request(toMsg(capsule(), "body"), pattern));
  EXPECT_FALSE(res.success);
  EXPECT_TRUE(contains(res.message, "panel 'front' (index 0)")) << res.message;
  EXPECT_TRUE(contains(res.message, "orientation")) << res.message;

  pattern = patternMsg(bag(), "body");
  pattern.seams[2].b_to = 7;  // no such outline point
  res = call(request(toMsg(capsule(), "body"), pattern));
  EXPECT_FALSE(res.success);
  EXPECT_TRUE(contains(res.message, "seam 2")) << res.message;
}

// A GarmentCode specification in the message: read at the request's spacing, placed on the body by
// the rule, sewn into one piece (the referee counts its loops).
TEST(DrapeService, DrapesAGarmentCodeSpecificationOnTheProceduralBody) {
  std::ifstream in(std::string(VIRTUAL_TRYON_SOURCE_DIR) + "/test/data/garmentcode/vest_specification.json");
  std::ostringstream text;
  text << in.rdbuf();
  ASSERT_FALSE(text.str().empty());
  vt::GarmentPattern pattern;
  pattern.header.frame_id = "body";
  pattern.garmentcode_json = text.str();
  const vt::TriMesh body = vt::makeProceduralBody();
  Drape::Request req = request(toMsg(body, "body"), pattern);
  req.spacing = 0;  // the node's drape/spacing
  Drape::Response res = call(req);
  // The plumbing: read, placed and sewn into one piece. (Its strain, which decides `converged`, is
  // the core's GarmentCodeDrape test: the node's float32 body gives a slightly different drape.)
  ASSERT_TRUE(res.success) << res.message;
  EXPECT_EQ(res.report.seams_open, 0u) << res.report.message;
  EXPECT_EQ(res.report.boundary_loops, res.report.openings);
  const vt::TriMesh g = returnedGarment(res);
  const vt::ReferenceCounts ref = vt::ReferenceReferee(body).count(g);  // the referee's predicates, on its tree
  EXPECT_EQ(ref.garment_edge_crossings, 0u);
  EXPECT_EQ(ref.body_edge_crossings, 0u);
  EXPECT_EQ(ref.vertices_inside, 0u);
  EXPECT_EQ(ref.boundary_loops, 4u);

  // Bad specifications fail with the place named; the node keeps serving.
  pattern.garmentcode_json = text.str().substr(0, text.str().size() / 2);
  res = call(request(toMsg(body, "body"), pattern));
  EXPECT_FALSE(res.success);
  EXPECT_TRUE(contains(res.message, "garmentcode_json: not valid JSON")) << res.message;
  pattern = patternMsg(bag(), "body");
  pattern.garmentcode_json = text.str();
  res = call(request(toMsg(body, "body"), pattern));
  EXPECT_FALSE(res.success);
  EXPECT_TRUE(contains(res.message, "both set")) << res.message;
}

TEST(DrapeService, PatternInAnotherFrameIsTransformedIntoTheBodyFrame) {
  // pattern_frame: the body frame moved by (1, 0, 0.5) and turned 90 degrees about y.
  const Eigen::Isometry3d bodyFromPattern =
      Eigen::Translation3d(1.0, 0, 0.5) * Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitY());
  tf2_ros::StaticTransformBroadcaster broadcaster;
  sendStaticTransform(broadcaster, "body", "pattern_frame", bodyFromPattern);

  // The same bag, with its placements expressed in pattern_frame.
  vt::Pattern p = bag();
  for (vt::PatternPanel& panel : p.panels) panel.placement.pose = bodyFromPattern.inverse() * panel.placement.pose;

  // The node's tf listener may need a moment for the static transform.
  Drape::Response res = retryWhile(
      [&] { return call(request(toMsg(capsule(), "body"), patternMsg(p, "pattern_frame"))); },
      [](const Drape::Response& r) { return contains(r.message, "no transform"); }, 15);
  expectDraped(res);  // only true when the bag landed on the capsule

  res = call(request(toMsg(capsule(), "body"), patternMsg(p, "no_such_frame")));
  EXPECT_FALSE(res.success);
  EXPECT_TRUE(contains(res.message, "pattern's frame 'no_such_frame'")) << res.message;
  EXPECT_TRUE(contains(res.message, "'body'")) << res.message;
}

}  // namespace

int main(int argc, char** argv) {
  return virtual_tryon_test::runClientTests(argc, argv, "drape_service_test");  // the spinner serves the markers
}
