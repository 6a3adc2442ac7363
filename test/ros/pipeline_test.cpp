// Client-side test of tryon_node's pipeline (started by pipeline.test): the ~drape_action action
// (feedback, result, cancel), two service clients at once while bodies stream in on ~body_mesh,
// and an unchanged body that costs nothing. Results are judged by the core's brute-force counter.
// Every wait is for a condition (a result, a feedback, a report of the body sent), with a deadline
// that fails the test.
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
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

namespace vt = virtual_tryon;
using virtual_tryon_test::bag;
using virtual_tryon_test::capsule;
using virtual_tryon_test::meshFromMsg;
using virtual_tryon_test::patternMsg;
using virtual_tryon_test::toMsg;
using virtual_tryon_test::waitUntil;
using Client = actionlib::SimpleActionClient<vt::DrapeGarmentAction>;

namespace {

// The ~drape request of the bag on the capsule.
vt::Drape bagDrape(double spacing) {
  vt::Drape srv;
  srv.request.body = toMsg(capsule(), "body");
  srv.request.pattern = patternMsg(bag(), "body");
  srv.request.spacing = spacing;
  return srv;
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
  const vt::ReferenceCounts c = vt::referenceCounts(capsule(), meshFromMsg(result->garment));
  EXPECT_EQ(c.garment_edge_crossings + c.body_edge_crossings + c.vertices_inside, 0u);

  // The service, same input: the same garment, vertex for vertex (the drape is deterministic).
  vt::Drape srv = bagDrape(0.03);
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
  ASSERT_TRUE(waitUntil([&] { return feedbacks >= 2; }, 60, 0.01)) << "no feedback while draping";
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
      const vt::ReferenceCounts c = vt::referenceCounts(scene.body, meshFromMsg(srv.response.garment));
      EXPECT_EQ(c.garment_edge_crossings + c.body_edge_crossings, 0u);
      ++resolved;
    }
  };
  auto draper = [&] {
    for (int k = 0; k < 2; ++k) {
      vt::Drape srv = bagDrape(0.03);
      ASSERT_TRUE(ros::service::call("/tryon_node/drape", srv));
      ASSERT_TRUE(srv.response.success) << srv.response.message;
      EXPECT_EQ(srv.response.report.seams_open, 0u);
      const vt::ReferenceCounts c = vt::referenceCounts(capsule(), meshFromMsg(srv.response.garment));
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

// Keeps every ~body_report the node sends, in order; publishes bodies on ~body_mesh. The latched
// report of an earlier body may arrive at any time after connecting, so a report is told apart by
// the body it describes: the same vertex and face counts and, flipped or not, the same enclosed
// volume.
struct BodyReports {
  ros::NodeHandle nh;
  std::mutex m;
  std::vector<vt::BodyReport> all;
  ros::Subscriber sub;
  ros::Publisher bodies;

  BodyReports() {
    sub = nh.subscribe<vt::BodyReport>("/tryon_node/body_report", 10,
                                       [this](const vt::BodyReport::ConstPtr& r) {
                                         std::lock_guard<std::mutex> l(m);
                                         all.push_back(*r);
                                       });
    bodies = nh.advertise<pcl_msgs::PolygonMesh>("/tryon_node/body_mesh", 5);
  }

  // Both ways connected to the node: what is published now reaches it, and its reports reach us.
  bool connected(double seconds) {
    return waitUntil([this] { return bodies.getNumSubscribers() > 0 && sub.getNumPublishers() > 0; }, seconds);
  }

  static bool describes(const vt::BodyReport& r, const vt::TriMesh& mesh) {
    const double volume = std::abs(vt::signedVolume(mesh));
    return r.vertices == static_cast<std::uint32_t>(mesh.V.rows()) &&
           r.faces == static_cast<std::uint32_t>(mesh.F.rows()) &&
           std::abs(std::abs(r.signed_volume) - volume) <= 1e-6 * volume;
  }

  // Index of the first report at or after `from` that describes `mesh`, waiting up to `seconds`
  // for it; -1 when none came.
  int waitForReportOf(const vt::TriMesh& mesh, std::size_t from, double seconds) {
    int found = -1;
    waitUntil(
        [&] {
          std::lock_guard<std::mutex> l(m);
          for (std::size_t i = from; i < all.size(); ++i)
            if (describes(all[i], mesh)) {
              found = static_cast<int>(i);
              return true;
            }
          return false;
        },
        seconds);
    return found;
  }

  // How many reports at or after `from` describe `mesh`.
  int countOf(const vt::TriMesh& mesh, std::size_t from) {
    std::lock_guard<std::mutex> l(m);
    int n = 0;
    for (std::size_t i = from; i < all.size(); ++i) n += describes(all[i], mesh);
    return n;
  }

  vt::BodyReport at(int i) {
    std::lock_guard<std::mutex> l(m);
    return all.at(static_cast<std::size_t>(i));
  }
};

TEST(Pipeline, AnUnchangedBodyIsNotProcessedAgain) {
  BodyReports reports;
  ASSERT_TRUE(reports.connected(10)) << "not connected to the node's ~body_mesh and ~body_report";
  const vt::TriMesh sphere = vt::makeSphere(0.25);
  const pcl_msgs::PolygonMesh body = toMsg(sphere, "body");
  reports.bodies.publish(body);
  const int first = reports.waitForReportOf(sphere, 0, 10);
  ASSERT_GE(first, 0) << "no report of the body within 10 s";
  for (int i = 1; i < 4; ++i) {
    ros::WallDuration(0.3).sleep();  // one at a time, as a sensor would send them
    reports.bodies.publish(body);
  }
  // Then a different body: the node takes its bodies in order, so once this one's report is in,
  // every copy of the first has been looked at.
  const vt::TriMesh other = vt::makeSphere(0.22);
  ros::WallDuration(0.3).sleep();
  reports.bodies.publish(toMsg(other, "body"));
  ASSERT_GE(reports.waitForReportOf(other, static_cast<std::size_t>(first) + 1, 10), 0)
      << "no report of the second body within 10 s";
  EXPECT_EQ(reports.countOf(sphere, static_cast<std::size_t>(first)), 1)
      << "the same body four times must be installed once";
  const vt::BodyReport r = reports.at(first);
  EXPECT_EQ(r.source, "mesh");
  EXPECT_TRUE(r.closed);
  EXPECT_GT(r.signed_volume, 0.0);
}

TEST(Pipeline, AnInvertedBodyIsFlippedWithAReport) {
  BodyReports reports;
  ASSERT_TRUE(reports.connected(10)) << "not connected to the node's ~body_mesh and ~body_report";
  vt::TriMesh inverted = vt::makeSphere(0.2);
  inverted.F.col(1).swap(inverted.F.col(2));
  reports.bodies.publish(toMsg(inverted, "body"));
  const int i = reports.waitForReportOf(inverted, 0, 10);
  ASSERT_GE(i, 0) << "no report of the body within 10 s";
  const vt::BodyReport r = reports.at(i);
  EXPECT_TRUE(r.flipped);
  EXPECT_GT(r.signed_volume, 0.0);
  EXPECT_NE(r.summary.find("flipped"), std::string::npos) << r.summary;
}

int main(int argc, char** argv) { return virtual_tryon_test::runClientTests(argc, argv, "pipeline_test", 2); }
