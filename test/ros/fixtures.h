// Shared by the rostests: small scenes the project makes, as messages.
#pragma once

#include "virtual_tryon/core/drape/pattern.h"
#include "virtual_tryon/core/scenes/procedural.h"
#include "virtual_tryon/ros/conversions.h"
#include "virtual_tryon/ros/pattern_conversions.h"

#include <Eigen/Geometry>
#include <pcl_msgs/PolygonMesh.h>
#include <ros/ros.h>
#include <virtual_tryon/GarmentPattern.h>

#include <cmath>
#include <string>

namespace virtual_tryon_test {

namespace vt = virtual_tryon;
namespace rc = virtual_tryon::ros_conversions;

// The body: capsule of radius 0.15 m with a 0.6 m cylinder along y, so its top is at y = 0.45.
inline vt::TriMesh capsule() { return vt::makeCapsule(0.15, 0.6); }

// A bag over the top of the capsule: two 0.6 x 0.3 m rectangles wrapped half a turn each on a
// 0.2 m cylinder about y (front facing +z; back turned half a turn about y), hem at y = 0.25,
// sewn along both sides into a tube and across the top, so that it rests on the cap.
inline vt::Pattern bag() {
  vt::Pattern p;
  p.name = "bag";
  for (int i = 0; i < 2; ++i) {
    vt::PatternPanel panel;
    panel.name = i == 0 ? "front" : "back";
    panel.outline.resize(4, 2);
    panel.outline << -0.3, 0.0, 0.3, 0.0, 0.3, 0.3, -0.3, 0.3;
    panel.placement.pose =
        Eigen::Translation3d(0, 0.25, 0) * Eigen::AngleAxisd(M_PI * i, Eigen::Vector3d::UnitY());
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

}  // namespace virtual_tryon_test
