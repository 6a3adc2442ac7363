// Shared by the rostests: wait for the node's latched MarkerArray and pick markers out of it.
#pragma once

#include <ros/ros.h>
#include <visualization_msgs/MarkerArray.h>

#include <mutex>
#include <string>

namespace virtual_tryon_test {

// Subscribes to `topic` and waits up to `seconds` (wall clock) for a MarkerArray; true when one
// arrived (the node's ~markers is latched, so the last one published arrives at once).
inline bool waitForMarkers(const std::string& topic, double seconds, visualization_msgs::MarkerArray& out) {
  std::mutex m;
  bool got = false;
  ros::NodeHandle nh;
  ros::Subscriber sub = nh.subscribe<visualization_msgs::MarkerArray>(
      topic, 1, [&](const visualization_msgs::MarkerArray::ConstPtr& a) {
        std::lock_guard<std::mutex> lock(m);
        out = *a;
        got = true;
      });
  const ros::WallTime deadline = ros::WallTime::now() + ros::WallDuration(seconds);
  while (ros::WallTime::now() < deadline) {
    {
      std::lock_guard<std::mutex> lock(m);
      if (got) return true;
    }
    ros::WallDuration(0.05).sleep();
  }
  std::lock_guard<std::mutex> lock(m);
  return got;
}

// The marker with namespace `ns` and `id`, or nullptr.
inline const visualization_msgs::Marker* findMarker(const visualization_msgs::MarkerArray& a, const std::string& ns,
                                                    int id) {
  for (const auto& mk : a.markers)
    if (mk.ns == ns && mk.id == id) return &mk;
  return nullptr;
}

}  // namespace virtual_tryon_test
