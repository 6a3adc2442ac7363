// Client-side test of tryon_node's pipeline (started by pipeline.test): the ~drape_action action
// (feedback, result, cancel), two service clients at once while bodies stream in on ~body_mesh,
// and an unchanged body that costs nothing. Results are judged by the core's brute-force counter.
#include "fixtures.h"
#include "virtual_tryon/testing/reference_check.h"

#include <actionlib/client/simple_action_client.h>
#include <gtest/gtest.h>
#include <pcl_msgs/PolygonMesh.h>
#include <ros/ros.h>
#include <virtual_tryon/BodyReport.h>
#include <virtual_tryon/Drape.h>
#include <virtual_tryon/DrapeGarmentAction.h>
#include <virtual_tryon/ResolvePenetration.h>

#include <atomic>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

namespace vt = virtual_tryon;
using virtual_tryon_test::bag;
using virtual_tryon_test::capsule;
using virtual_tryon_test::patternMsg;
using virtual_tryon_test::toMsg;
using Client = actionlib::SimpleActionClient<vt::DrapeGarmentAction>;

namespace {

vt::TriMesh mesh(const pcl_msgs::PolygonMesh& msg) {
  vt::TriMesh out;
  std::string error;
  EXPECT_TRUE(vt::ros_conversions::fromMsg(msg, out, error)) << error;
  return out;
}

vt::DrapeGarmentGoal bagGoal(double spacing) {
  vt::DrapeGarmentGoal goal;
  goal.body = toMsg(capsule(), "body");
  goal.pattern = patternMsg(bag(), "body");
  goal.spacing = spacing;
  return goal;
}

}  // namespace

TEST(Pipeline, DrapeActionGivesFeedbackAndTheSameResultAsTheService) {
  Client client("/tryon_node/drape_action", true);
  ASSERT_TRUE(client.waitForServer(ros::Duration(30)));
  std::mutex m;
  std::vector<vt::DrapeGarmentFeedback> feedback;
  client.sendGoal(bagGoal(0.03), Client::SimpleDoneCallback(), Client::SimpleActiveCallback(),
                  [&](const vt::DrapeGarmentFeedbackConstPtr& f) {
                    std::lock_guard<std::mutex> l(m);
                    feedback.push_back(*f);
                  });
  ASSERT_TRUE(client.waitForResult(ros::Duration(120)));
  EXPECT_EQ(client.getState(), actionlib::SimpleClientGoalState::SUCCEEDED);
  const auto result = client.getResult();
  ASSERT_TRUE(result);
  EXPECT_TRUE(result->success) << result->message;
  EXPECT_TRUE(result->report.converged) << result->message;
  {
    std::lock_guard<std::mutex> l(m);
    ASSERT_GT(feedback.size(), 1u);
    for (std::size_t i = 1; i < feedback.size(); ++i) {
      EXPECT_GT(feedback[i].iteration, feedback[i - 1].iteration);
      EXPECT_GE(feedback[i].seconds, feedback[i - 1].seconds);
    }
    EXPECT_TRUE(feedback.front().sewing);
    EXPECT_GT(feedback.front().seam_gap, 0.0);
  }
  const vt::ReferenceCounts c = vt::referenceCounts(capsule(), mesh(result->garment));
  EXPECT_EQ(c.garment_edge_crossings + c.body_edge_crossings + c.vertices_inside, 0u);

  // The service, same input: the same garment, vertex for vertex (the drape is deterministic).
  vt::Drape srv;
  srv.request.body = toMsg(capsule(), "body");
  srv.request.pattern = patternMsg(bag(), "body");
  srv.request.spacing = 0.03;
  ASSERT_TRUE(ros::service::call("/tryon_node/drape", srv));
  ASSERT_TRUE(srv.response.success) << srv.response.message;
  EXPECT_EQ(srv.response.report.iterations, result->report.iterations);
  EXPECT_EQ(srv.response.garment.cloud.data, result->garment.cloud.data);
  EXPECT_EQ(srv.response.garment.polygons.size(), result->garment.polygons.size());
}

TEST(Pipeline, DrapeActionCanBeCancelled) {
  Client client("/tryon_node/drape_action", true);
  ASSERT_TRUE(client.waitForServer(ros::Duration(30)));
  std::atomic<int> feedbacks{0};
  vt::DrapeGarmentGoal goal = bagGoal(0.008);  // fine: thousands of vertices, seconds of work
  goal.max_iterations = 200000;
  const ros::WallTime start = ros::WallTime::now();
  client.sendGoal(goal, Client::SimpleDoneCallback(), Client::SimpleActiveCallback(),
                  [&](const vt::DrapeGarmentFeedbackConstPtr&) { ++feedbacks; });
  const ros::WallTime deadline = ros::WallTime::now() + ros::WallDuration(60);
  while (feedbacks < 2 && ros::WallTime::now() < deadline) ros::WallDuration(0.01).sleep();
  ASSERT_GE(feedbacks.load(), 2) << "no feedback while draping";
  client.cancelGoal();
  ASSERT_TRUE(client.waitForResult(ros::Duration(30)));
  EXPECT_EQ(client.getState(), actionlib::SimpleClientGoalState::PREEMPTED);
  const auto result = client.getResult();
  ASSERT_TRUE(result);
  EXPECT_TRUE(result->report.cancelled) << result->message;
  EXPECT_FALSE(result->report.converged);
  EXPECT_LT((ros::WallTime::now() - start).toSec(), 60.0);
}

TEST(Pipeline, TwoClientsAtOnceWhileBodiesStreamIn) {
  ASSERT_TRUE(ros::service::waitForService("/tryon_node/resolve_penetration", ros::Duration(30)));
  ros::NodeHandle nh;
  ros::Publisher bodies = nh.advertise<pcl_msgs::PolygonMesh>("/tryon_node/body_mesh", 2);
  std::atomic<bool> streaming{true};
  std::thread streamer([&] {
    // Bodies at 10 Hz, alternating two shapes, so that each one is new.
    const pcl_msgs::PolygonMesh a = toMsg(capsule(), "body");
    const pcl_msgs::PolygonMesh b = toMsg(vt::makeSphere(0.3), "body");
    for (int i = 0; streaming; ++i) {
      bodies.publish(i % 2 ? a : b);
      ros::WallDuration(0.1).sleep();
    }
  });
  const vt::ResolveScene scene = vt::makeWrinkledTubeScene();
  std::atomic<int> resolved{0}, draped{0};
  auto resolver = [&] {
    for (int k = 0; k < 3; ++k) {
      vt::ResolvePenetration srv;
      srv.request.body = toMsg(scene.body, "body");
      srv.request.garment = toMsg(scene.garment, "body");
      ASSERT_TRUE(ros::service::call("/tryon_node/resolve_penetration", srv));
      ASSERT_TRUE(srv.response.success) << srv.response.message;
      const vt::ReferenceCounts c = vt::referenceCounts(scene.body, mesh(srv.response.garment));
      EXPECT_EQ(c.garment_edge_crossings + c.body_edge_crossings, 0u);
      ++resolved;
    }
  };
  auto draper = [&] {
    for (int k = 0; k < 2; ++k) {
      vt::Drape srv;
      srv.request.body = toMsg(capsule(), "body");
      srv.request.pattern = patternMsg(bag(), "body");
      srv.request.spacing = 0.03;
      ASSERT_TRUE(ros::service::call("/tryon_node/drape", srv));
      ASSERT_TRUE(srv.response.success) << srv.response.message;
      EXPECT_EQ(srv.response.report.seams_open, 0u);
      const vt::ReferenceCounts c = vt::referenceCounts(capsule(), mesh(srv.response.garment));
      EXPECT_EQ(c.garment_edge_crossings + c.body_edge_crossings + c.vertices_inside, 0u);
      ++draped;
    }
  };
  const ros::WallTime start = ros::WallTime::now();
  std::thread t1(resolver), t2(draper);
  t1.join();
  t2.join();
  streaming = false;
  streamer.join();
  EXPECT_EQ(resolved.load(), 3);
  EXPECT_EQ(draped.load(), 2);
  EXPECT_LT((ros::WallTime::now() - start).toSec(), 120.0);
  // Still serving: the empty request uses the latest streamed body.
  vt::ResolvePenetration srv;
  srv.request.garment = toMsg(scene.garment, "body");
  ASSERT_TRUE(ros::service::call("/tryon_node/resolve_penetration", srv));
  EXPECT_FALSE(srv.response.message.empty());
}

// Counts the node's ~body_report messages and keeps the last; publishes bodies on ~body_mesh.
struct BodyReports {
  ros::NodeHandle nh;
  std::mutex m;
  vt::BodyReport last;
  std::atomic<int> count{0};
  ros::Subscriber sub;
  ros::Publisher bodies;

  BodyReports() {
    sub = nh.subscribe<vt::BodyReport>("/tryon_node/body_report", 10,
                                       [this](const vt::BodyReport::ConstPtr& r) {
                                         std::lock_guard<std::mutex> l(m);
                                         last = *r;
                                         ++count;
                                       });
    bodies = nh.advertise<pcl_msgs::PolygonMesh>("/tryon_node/body_mesh", 5);
    const ros::WallTime deadline = ros::WallTime::now() + ros::WallDuration(10);
    while (bodies.getNumSubscribers() == 0 && ros::WallTime::now() < deadline)
      ros::WallDuration(0.05).sleep();
    ros::WallDuration(1.0).sleep();  // the latched report of an earlier body arrives first
  }
};

TEST(Pipeline, AnUnchangedBodyIsNotProcessedAgain) {
  BodyReports reports;
  const int before = reports.count;
  const pcl_msgs::PolygonMesh body = toMsg(vt::makeSphere(0.25), "body");
  for (int i = 0; i < 4; ++i) {
    reports.bodies.publish(body);
    ros::WallDuration(0.3).sleep();
  }
  ros::WallDuration(1.0).sleep();
  EXPECT_EQ(reports.count - before, 1) << "the same body four times must be installed once";
  std::lock_guard<std::mutex> l(reports.m);
  EXPECT_EQ(reports.last.source, "mesh");
  EXPECT_TRUE(reports.last.closed);
  EXPECT_GT(reports.last.signed_volume, 0.0);
}

TEST(Pipeline, AnInvertedBodyIsFlippedWithAReport) {
  BodyReports reports;
  const int before = reports.count;
  vt::TriMesh inverted = vt::makeSphere(0.2);
  inverted.F.col(1).swap(inverted.F.col(2));
  reports.bodies.publish(toMsg(inverted, "body"));
  const ros::WallTime until = ros::WallTime::now() + ros::WallDuration(10);
  while (reports.count == before && ros::WallTime::now() < until) ros::WallDuration(0.05).sleep();
  ASSERT_GT(reports.count - before, 0);
  std::lock_guard<std::mutex> l(reports.m);
  EXPECT_TRUE(reports.last.flipped);
  EXPECT_GT(reports.last.signed_volume, 0.0);
  EXPECT_NE(reports.last.summary.find("flipped"), std::string::npos) << reports.last.summary;
}

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "pipeline_test");
  ros::AsyncSpinner spinner(2);
  spinner.start();
  return RUN_ALL_TESTS();
}
