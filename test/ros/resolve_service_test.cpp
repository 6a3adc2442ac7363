// Client-side test of tryon_node (started by resolve_service.test): the service on real geometry,
// judged by the core's independent brute-force counter (reference_check.h), the latched markers,
// bad input, the topic fallback and tf frames. Tests run in the order written: the first one needs
// a node that has not received anything on its topics yet.
#include "virtual_tryon/core/geometry/mesh.h"
#include "virtual_tryon/core/scenes/procedural.h"
#include "virtual_tryon/testing/reference_check.h"
#include "virtual_tryon/ros/conversions.h"

#include "fixtures.h"
#include "marker_wait.h"

#include <gtest/gtest.h>

#include <geometry_msgs/TransformStamped.h>
#include <pcl_msgs/PolygonMesh.h>
#include <ros/ros.h>
#include <tf2_ros/static_transform_broadcaster.h>
#include <tf2_ros/transform_broadcaster.h>
#include <virtual_tryon/ResolvePenetration.h>
#include <visualization_msgs/MarkerArray.h>

#include <Eigen/Geometry>

#include <chrono>
#include <cmath>
#include <limits>
#include <memory>
#include <mutex>
#include <string>

namespace vt = virtual_tryon;
namespace rc = virtual_tryon::ros_conversions;
using vt::ResolvePenetration;

namespace {

const std::string kService = "/tryon_node/resolve_penetration";

using virtual_tryon_test::callService;
using virtual_tryon_test::contains;
using virtual_tryon_test::meshFromMsg;
using virtual_tryon_test::retryWhile;
using virtual_tryon_test::sendStaticTransform;
using virtual_tryon_test::toMsg;

// Whether a response says the node is not ready yet: `what` is in its message.
auto says(const std::string& what) {
  return [what](const ResolvePenetration::Response& r) { return contains(r.message, what); };
}

// Calls the service; gtest assertion failures when the service is not there or the call fails.
ResolvePenetration::Response call(const pcl_msgs::PolygonMesh& body,
                                  const pcl_msgs::PolygonMesh& garment, double clearance = 0,
                                  unsigned maxIterations = 0) {
  ResolvePenetration srv;
  srv.request.body = body;
  srv.request.garment = garment;
  srv.request.clearance = clearance;
  srv.request.max_iterations = maxIterations;
  return callService(kService, srv);
}

// The returned garment, converted back; fails the test when it does not convert.
vt::TriMesh returnedGarment(const ResolvePenetration::Response& res) { return meshFromMsg(res.garment); }

// The result is the input's mesh (same order and faces) with no crossing left, by the referee.
void expectResolved(const vt::TriMesh& body, const vt::TriMesh& input,
                    const ResolvePenetration::Response& res) {
  EXPECT_TRUE(res.success) << res.message;
  EXPECT_TRUE(res.report.converged) << res.report.reason;
  EXPECT_FALSE(res.message.empty());
  EXPECT_EQ(res.report.garment_edge_crossings_after, 0u);
  EXPECT_EQ(res.report.body_edge_crossings_after, 0u);
  const vt::TriMesh out = returnedGarment(res);
  ASSERT_EQ(out.numVertices(), input.numVertices());
  ASSERT_EQ(out.numFaces(), input.numFaces());
  EXPECT_TRUE(out.F == input.F) << "faces changed";
  const vt::ReferenceCounts ref = vt::referenceCounts(body, out);
  EXPECT_EQ(ref.garment_edge_crossings, 0u);
  EXPECT_EQ(ref.body_edge_crossings, 0u);
  EXPECT_EQ(ref.vertices_inside, 0u) << "deepest " << ref.max_depth << " m";
}

double maxDistance(const vt::MatrixX3d& a, const vt::MatrixX3d& b) {
  return (a - b).rowwise().norm().maxCoeff();
}

// ---------------------------------------------------------------------------------------------
// Must run first: nothing has been published on the node's topics yet.
TEST(TryonNode, EmptyBodyOrGarmentWithoutTopicDataFails) {
  const vt::ResolveScene s = vt::makeWrinkledTubeScene();
  const pcl_msgs::PolygonMesh empty;

  ResolvePenetration::Response res = call(empty, toMsg(s.garment, "body"));
  EXPECT_FALSE(res.success);
  EXPECT_TRUE(contains(res.message, "no body")) << res.message;
  EXPECT_TRUE(contains(res.message, "body_mesh")) << res.message;
  EXPECT_EQ(res.garment.polygons.size(), 0u);

  res = call(toMsg(s.body, "body"), empty);
  EXPECT_FALSE(res.success);
  EXPECT_TRUE(contains(res.message, "no garment")) << res.message;
  EXPECT_TRUE(contains(res.message, "garment_mesh")) << res.message;
}

TEST(TryonNode, ResolvesTheWrinkledTubeWithNoCrossingLeft) {
  const vt::ResolveScene s = vt::makeWrinkledTubeScene();
  const vt::ReferenceCounts before = vt::referenceCounts(s.body, s.garment);
  ASSERT_GT(before.garment_edge_crossings + before.body_edge_crossings, 0u) << "scene does not penetrate";

  const ResolvePenetration::Response res = call(toMsg(s.body, "body"), toMsg(s.garment, "body"));
  expectResolved(s.body, s.garment, res);
  EXPECT_GT(res.report.garment_edge_crossings_before + res.report.body_edge_crossings_before, 0u);
  // The node's default objective (config/params.yaml): the rounds, then the shape relaxation.
  EXPECT_EQ(res.report.objective, "smooth");
  EXPECT_TRUE(res.report.relaxed);
  EXPECT_GT(res.report.relaxation_sweeps, 0u);
  EXPECT_LE(res.report.max_edge_strain, 0.3);
  EXPECT_GT(res.report.moved_vertices, 0u);
  EXPECT_TRUE(res.report.body_closed);
  EXPECT_GT(res.report.clearance, 0.0);
  EXPECT_EQ(res.garment.header.frame_id, "body");
  // Minimal displacement: wrinkles dip at most 1.5 cm, nothing should travel far.
  const vt::TriMesh out = returnedGarment(res);
  ASSERT_EQ(out.numVertices(), s.garment.numVertices());
  EXPECT_LT(maxDistance(out.V, s.garment.V), 0.03);
  EXPECT_NEAR(res.report.max_displacement, maxDistance(out.V, s.garment.V), 1e-5);
}

TEST(TryonNode, RequestClearanceAndIterationLimitOverrideTheParameters) {
  const vt::ResolveScene s = vt::makeWrinkledTubeScene();
  ResolvePenetration::Response res =
      call(toMsg(s.body, "body"), toMsg(s.garment, "body"), /*clearance=*/0.004);
  expectResolved(s.body, s.garment, res);
  EXPECT_DOUBLE_EQ(res.report.clearance, 0.004);

  res = call(toMsg(s.body, "body"), toMsg(s.garment, "body"), 0, /*maxIterations=*/1);
  EXPECT_LE(res.report.iterations, 1u);
  EXPECT_EQ(res.success, static_cast<bool>(res.report.converged));
  EXPECT_FALSE(res.message.empty());
}

TEST(TryonNode, PublishesBodyAndGarmentMarkers) {
  const vt::ResolveScene s = vt::makeWrinkledTubeScene(48, 30);  // sizes unlike the other tests
  const ResolvePenetration::Response res = call(toMsg(s.body, "body"), toMsg(s.garment, "body"));
  ASSERT_TRUE(res.success) << res.message;
  const vt::TriMesh out = returnedGarment(res);

  const virtual_tryon_test::NodeMarkers markers = virtual_tryon_test::waitForNodeMarkers();
  ASSERT_TRUE(markers.received) << "no MarkerArray on /tryon_node/markers within 10 s";
  const visualization_msgs::Marker *body = markers.body(), *garment = markers.garment();
  ASSERT_NE(body, nullptr);
  ASSERT_NE(garment, nullptr);
  for (const auto* mk : {body, garment}) {
    EXPECT_EQ(mk->type, visualization_msgs::Marker::TRIANGLE_LIST);
    EXPECT_EQ(mk->action, visualization_msgs::Marker::ADD);
    EXPECT_EQ(mk->header.frame_id, "body");
  }
  EXPECT_NEAR(body->color.a, 0.4, 1e-6);
  EXPECT_NEAR(body->color.r, body->color.g, 1e-6);  // grey
  ASSERT_EQ(body->points.size(), 3u * static_cast<std::size_t>(s.body.numFaces()));
  ASSERT_EQ(garment->points.size(), 3u * static_cast<std::size_t>(out.numFaces()));
  // The garment marker is the fitted garment, not the input.
  double worst = 0;
  for (Eigen::Index f = 0; f < out.numFaces(); ++f)
    for (int k = 0; k < 3; ++k) {
      const auto& p = garment->points[static_cast<std::size_t>(3 * f + k)];
      worst = std::max(worst, (Eigen::Vector3d(p.x, p.y, p.z) -
                               Eigen::Vector3d(out.V.row(out.F(f, k)).transpose())).norm());
    }
  EXPECT_LT(worst, 1e-5);
}

TEST(TryonNode, BadInputFailsWithAReasonAndTheNodeKeepsServing) {
  const vt::ResolveScene s = vt::makeWrinkledTubeScene();
  pcl_msgs::PolygonMesh bad = toMsg(s.garment, "body");
  const std::uint32_t badIndex = static_cast<std::uint32_t>(s.garment.numVertices()) + 7;
  bad.polygons[5].vertices[1] = badIndex;
  ResolvePenetration::Response res = call(toMsg(s.body, "body"), bad);
  EXPECT_FALSE(res.success);
  EXPECT_TRUE(contains(res.message, "garment")) << res.message;
  EXPECT_TRUE(contains(res.message, std::to_string(badIndex))) << res.message;
  EXPECT_TRUE(contains(res.message, "polygon 5")) << res.message;

  vt::TriMesh nanBody = s.body;
  nanBody.V(3, 1) = std::numeric_limits<double>::quiet_NaN();
  res = call(toMsg(nanBody, "body"), toMsg(s.garment, "body"));
  EXPECT_FALSE(res.success);
  EXPECT_TRUE(contains(res.message, "body")) << res.message;
  EXPECT_TRUE(contains(res.message, "NaN")) << res.message;

  res = call(toMsg(s.body, "body"), toMsg(s.garment, "body"));
  expectResolved(s.body, s.garment, res);
}

TEST(TryonNode, EmptyRequestUsesTheLatestTopicData) {
  const vt::ResolveScene s = vt::makeWrinkledTubeScene(40, 24);  // sizes unlike the other tests
  ros::NodeHandle nh;
  ros::Publisher bodyPub = nh.advertise<pcl_msgs::PolygonMesh>("/tryon_node/body_mesh", 1, true);
  ros::Publisher garmentPub = nh.advertise<pcl_msgs::PolygonMesh>("/tryon_node/garment_mesh", 1, true);
  bodyPub.publish(toMsg(s.body, "body"));
  garmentPub.publish(toMsg(s.garment, "body"));

  // Until the node has both messages it answers "none has been received".
  const pcl_msgs::PolygonMesh empty;
  ResolvePenetration::Response res = retryWhile([&] { return call(empty, empty); }, says("received"), 15);
  expectResolved(s.body, s.garment, res);
  EXPECT_GT(res.report.garment_edge_crossings_before + res.report.body_edge_crossings_before, 0u);

  // A bad body on the topic is rejected; the previous one keeps being used.
  pcl_msgs::PolygonMesh bad = toMsg(s.body, "body");
  bad.polygons[0].vertices[2] = 1000000;
  bodyPub.publish(bad);
  ros::WallDuration(1.0).sleep();
  res = call(empty, empty);
  expectResolved(s.body, s.garment, res);

  // An empty garment with an explicit body mixes request and topic data.
  const vt::ResolveScene other = vt::makeWrinkledTubeScene();
  res = call(toMsg(other.body, "body"), empty);
  expectResolved(other.body, s.garment, res);
}

TEST(TryonNode, GarmentInAnotherFrameIsTransformedIntoTheBodyFrame) {
  const vt::ResolveScene s = vt::makeWrinkledTubeScene();
  // garment_frame is body translated by (0.5, 0, 0) and turned 90 degrees about z.
  const Eigen::Isometry3d bodyFromGarment =
      Eigen::Translation3d(0.5, 0, 0) * Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitZ());
  tf2_ros::StaticTransformBroadcaster broadcaster;
  sendStaticTransform(broadcaster, "body", "garment_frame", bodyFromGarment);

  vt::TriMesh inGarmentFrame = s.garment;
  const Eigen::Isometry3d garmentFromBody = bodyFromGarment.inverse();
  for (Eigen::Index i = 0; i < inGarmentFrame.numVertices(); ++i)
    inGarmentFrame.V.row(i) = (garmentFromBody * Eigen::Vector3d(s.garment.V.row(i).transpose())).transpose();
  ASSERT_GT(maxDistance(inGarmentFrame.V, s.garment.V), 0.3);  // really elsewhere

  // The node's tf listener may need a moment to receive the static transform.
  const ResolvePenetration::Response res = retryWhile(
      [&] { return call(toMsg(s.body, "body"), toMsg(inGarmentFrame, "garment_frame")); }, says("no transform"), 15);

  expectResolved(s.body, s.garment, res);
  EXPECT_EQ(res.garment.header.frame_id, "body");
  EXPECT_GT(res.report.garment_edge_crossings_before + res.report.body_edge_crossings_before, 0u)
      << "the garment did not land on the body";
  // Vertices the resolver did not move are back where they were in the body frame.
  const vt::TriMesh out = returnedGarment(res);
  ASSERT_EQ(out.numVertices(), s.garment.numVertices());
  const Eigen::VectorXd d = (out.V - s.garment.V).rowwise().norm();
  const auto unmoved = static_cast<unsigned>((d.array() < 1e-4).count());
  EXPECT_GE(unmoved + res.report.moved_vertices, static_cast<unsigned>(out.numVertices()));
  // (The smooth objective moves the whole tube a little.) Every vertex is within the resolver's own
  // largest move of where it was in the body frame: a wrong transform would put it 0.5 m away.
  EXPECT_LE(d.maxCoeff(), res.report.max_displacement + 1e-5);
  EXPECT_LT(d.maxCoeff(), 0.03);
  const Eigen::RowVector3d meanOut = out.V.colwise().mean(), meanIn = s.garment.V.colwise().mean();
  EXPECT_LT((meanOut - meanIn).norm(), 2e-3);
}

TEST(TryonNode, UnknownGarmentFrameFailsWithinTheTimeout) {
  const vt::ResolveScene s = vt::makeWrinkledTubeScene();
  const auto start = std::chrono::steady_clock::now();
  const ResolvePenetration::Response res =
      call(toMsg(s.body, "body"), toMsg(s.garment, "no_such_frame"));
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  EXPECT_FALSE(res.success);
  EXPECT_TRUE(contains(res.message, "'no_such_frame'")) << res.message;
  EXPECT_TRUE(contains(res.message, "'body'")) << res.message;
  EXPECT_LT(seconds, 5.0) << "tf_timeout is 0.5 s";
}

}  // namespace

int main(int argc, char** argv) {
  return virtual_tryon_test::runClientTests(argc, argv, "resolve_service_test");  // the spinner serves the markers
}

TEST(TryonNode, AStaleGarmentTransformFailsWithinTheTimeout) {
  // A moving frame whose only transform is 30 s old; the garment is stamped now.
  static tf2_ros::TransformBroadcaster broadcaster;
  geometry_msgs::TransformStamped t;
  t.header.frame_id = "body";
  t.child_frame_id = "stale_frame";
  t.header.stamp = ros::Time::now() - ros::Duration(30.0);
  t.transform.rotation.w = 1.0;
  for (int i = 0; i < 5; ++i) {  // the node's listener may still be connecting
    broadcaster.sendTransform(t);
    ros::WallDuration(0.1).sleep();
  }
  const vt::ResolveScene s = vt::makeWrinkledTubeScene();
  const auto start = std::chrono::steady_clock::now();
  const ResolvePenetration::Response res =
      call(toMsg(s.body, "body"), toMsg(s.garment, "stale_frame"));
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  EXPECT_FALSE(res.success);
  EXPECT_TRUE(contains(res.message, "stale")) << res.message;
  EXPECT_TRUE(contains(res.message, "'stale_frame'")) << res.message;
  EXPECT_LT(seconds, 5.0) << "tf_timeout is 0.5 s";
  // The same garment stamped when the transform was valid goes through.
  pcl_msgs::PolygonMesh old = toMsg(s.garment, "stale_frame");
  old.header.stamp = t.header.stamp;
  old.cloud.header.stamp = t.header.stamp;
  EXPECT_TRUE(call(toMsg(s.body, "body"), old).success);
}
