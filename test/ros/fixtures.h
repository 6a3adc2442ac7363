// Shared by the rostests: small scenes the project makes, as messages; service calls, condition
// waits and tf set-up.
#pragma once

#include "virtual_tryon/core/drape/pattern.h"
#include "virtual_tryon/core/scenes/procedural.h"
#include "virtual_tryon/ros/conversions.h"
#include "virtual_tryon/ros/pattern_conversions.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <geometry_msgs/TransformStamped.h>
#include <pcl_msgs/PolygonMesh.h>
#include <ros/ros.h>
#include <tf2_ros/static_transform_broadcaster.h>
#include <virtual_tryon/GarmentPattern.h>

#include <cmath>
#include <string>

namespace virtual_tryon_test {

namespace vt = virtual_tryon;
namespace rc = virtual_tryon::ros_conversions;

// The body: capsule of radius 0.15 m with a 0.6 m cylinder along y, so its top is at y = 0.45.
inline vt::TriMesh capsule() { return vt::makeCapsule(0.15, 0.6); }

// A bag over the top of the capsule: two 0.6 x 0.3 m rectangles wrapped half a turn each on a
// 0.2 m cylinder about y (front facing +z; back turned half a turn about y), their hems' middle at
// `at` (by default y = 0.25 on the axis), sewn along both sides into a tube and across the top, so
// that it rests on the cap.
inline vt::Pattern bag(const Eigen::Vector3d& at = Eigen::Vector3d(0, 0.25, 0)) {
  vt::Pattern p;
  p.name = "bag";
  for (int i = 0; i < 2; ++i) {
    vt::PatternPanel panel;
    panel.name = i == 0 ? "front" : "back";
    panel.outline.resize(4, 2);
    panel.outline << -0.3, 0.0, 0.3, 0.0, 0.3, 0.3, -0.3, 0.3;
    panel.placement.pose = Eigen::Translation3d(at) * Eigen::AngleAxisd(M_PI * i, Eigen::Vector3d::UnitY());
    panel.placement.wrap_radius = 0.2;
    p.panels.push_back(panel);
  }
  vt::PatternSeam right, left, top;
  right.a = {0, 1, 2};  // front's +x side, hem to top ...
  right.b = {1, 0, 3};  // ... meets the back's side on +x
  left.a = {0, 0, 3};
  left.b = {1, 1, 2};
  top.a = {0, 2, 3};  // front's top edge from +x to -x ...
  top.b = {1, 3, 2};  // ... meets the back's top edge from +x to -x
  p.seams = {right, left, top};
  return p;
}

inline pcl_msgs::PolygonMesh toMsg(const vt::TriMesh& mesh, const std::string& frame) {
  std_msgs::Header h;
  h.frame_id = frame;
  h.stamp = ros::Time::now();
  pcl_msgs::PolygonMesh msg;
  rc::toMsg(mesh, h, msg);
  return msg;
}

inline vt::GarmentPattern patternMsg(const vt::Pattern& p, const std::string& frame) {
  std_msgs::Header h;
  h.frame_id = frame;
  return rc::toMsg(p, h);
}

inline bool contains(const std::string& s, const std::string& part) { return s.find(part) != std::string::npos; }

// The mesh of a message; a failure of the calling test (and an empty mesh) when it does not convert.
inline vt::TriMesh meshFromMsg(const pcl_msgs::PolygonMesh& msg) {
  vt::TriMesh out;
  std::string error;
  EXPECT_TRUE(rc::fromMsg(msg, out, error)) << error;
  return out;
}

// Calls the service `name` with `srv`'s request once it is there (up to `waitSeconds`); gtest
// failures when it never comes up or the call itself fails (the response is then the default).
template <class Service>
typename Service::Response callService(const std::string& name, Service srv, double waitSeconds = 30) {
  EXPECT_TRUE(ros::service::waitForService(name, ros::Duration(waitSeconds))) << name << " never came up";
  EXPECT_TRUE(ros::service::call(name, srv)) << "the call itself failed (node died?)";
  return srv.response;
}

// Asks `done` every `pause` seconds until it answers true or `seconds` (wall clock) have passed;
// returns its last answer. What `done` looks at is changed by callbacks on a spinner thread.
template <class Done>
bool waitUntil(Done done, double seconds, double pause = 0.05) {
  const ros::WallTime deadline = ros::WallTime::now() + ros::WallDuration(seconds);
  while (ros::WallTime::now() < deadline) {
    if (done()) return true;
    ros::WallDuration(pause).sleep();
  }
  return done();
}

// Calls `call` again, `pause` seconds apart, while `again` says its result is worth retrying
// (the node not ready yet) and `seconds` (wall clock, from the first call) have not passed;
// returns the last result.
template <class Call, class Again>
auto retryWhile(Call call, Again again, double seconds, double pause = 0.2) -> decltype(call()) {
  const ros::WallTime deadline = ros::WallTime::now() + ros::WallDuration(seconds);
  decltype(call()) result;
  do {
    result = call();
    if (!again(result)) break;
    ros::WallDuration(pause).sleep();
  } while (ros::WallTime::now() < deadline);
  return result;
}

// Sends `parentFromChild` on `broadcaster` as the static transform parent -> child, stamped now.
inline void sendStaticTransform(tf2_ros::StaticTransformBroadcaster& broadcaster, const std::string& parent,
                                const std::string& child, const Eigen::Isometry3d& parentFromChild) {
  geometry_msgs::TransformStamped t;
  t.header.stamp = ros::Time::now();
  t.header.frame_id = parent;
  t.child_frame_id = child;
  t.transform.translation.x = parentFromChild.translation().x();
  t.transform.translation.y = parentFromChild.translation().y();
  t.transform.translation.z = parentFromChild.translation().z();
  const Eigen::Quaterniond q(parentFromChild.rotation());
  t.transform.rotation.x = q.x();
  t.transform.rotation.y = q.y();
  t.transform.rotation.z = q.z();
  t.transform.rotation.w = q.w();
  broadcaster.sendTransform(t);
}

// The main() of a client test: gtest and ROS set up, a node handle held for the whole run (it
// starts the node) and `spinnerThreads` threads serving subscriptions and action clients in the
// background while the tests run.
inline int runClientTests(int argc, char** argv, const std::string& node, int spinnerThreads = 1) {
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, node);
  ros::NodeHandle nh;
  ros::AsyncSpinner spinner(spinnerThreads);
  spinner.start();
  const int result = RUN_ALL_TESTS();
  spinner.stop();
  ros::shutdown();
  return result;
}

}  // namespace virtual_tryon_test
