// Shared by the rostests: wait for the node's latched MarkerArray and pick markers out of it.
#pragma once

#include "fixtures.h"

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
  return waitUntil(
      [&] {
        std::lock_guard<std::mutex> lock(m);
        return got;
      },
      seconds);
}

// The marker with namespace `ns` and `id`, or nullptr.
inline const visualization_msgs::Marker* findMarker(const visualization_msgs::MarkerArray& a, const std::string& ns,
                                                    int id) {
  for (const auto& mk : a.markers)
    if (mk.ns == ns && mk.id == id) return &mk;
  return nullptr;
}

// What tryon_node shows on its latched ~markers: the body (namespace "body", id 0), the garment
// ("garment", 1) and the vertices the last fit moved ("moved", 2); nullptr when missing.
struct NodeMarkers {
  bool received = false;  // a MarkerArray arrived in time
  visualization_msgs::MarkerArray array;
  const visualization_msgs::Marker* body() const { return findMarker(array, "body", 0); }
  const visualization_msgs::Marker* garment() const { return findMarker(array, "garment", 1); }
  const visualization_msgs::Marker* moved() const { return findMarker(array, "moved", 2); }
};

// Waits up to `seconds` for the node's markers on /tryon_node/markers.
inline NodeMarkers waitForNodeMarkers(double seconds = 10.0) {
  NodeMarkers m;
  m.received = waitForMarkers("/tryon_node/markers", seconds, m.array);
  return m;
}

}  // namespace virtual_tryon_test
