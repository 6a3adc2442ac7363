// The ROS face of the penetration resolver: topics for the latest body and garment, a service that
// resolves a garment against a body, latched results for RViz. All algorithms live in the core;
// this class only converts messages, reads parameters, transforms frames and keeps state.
//
// Threading: every callback may run on any spinner thread. The shared state (latest body,
// latest garment, cached request body) is a set of pointers to immutable objects swapped under
// `mutex_`; a resolve copies what it needs under the lock and works without it, so a long resolve
// never blocks the topics and two resolves may run at once (the Body's BVH is built thread-safely).
#pragma once

#include "virtual_tryon/core/body.h"
#include "virtual_tryon/core/mesh.h"
#include "virtual_tryon/core/penetration_resolver.h"

#include <pcl_msgs/PolygonMesh.h>
#include <ros/ros.h>
#include <std_msgs/Header.h>
#include <tf2_ros/buffer.h>
#include <tf2_ros/transform_listener.h>
#include <virtual_tryon/ResolvePenetration.h>

#include <memory>
#include <mutex>
#include <string>

namespace virtual_tryon {

class TryonNode {
 public:
  // Parameters, topics and the service live in `pnh` (normally "~"); `nh` is kept for future
  // global names.
  TryonNode(ros::NodeHandle nh, ros::NodeHandle pnh);

  TryonNode(const TryonNode&) = delete;
  TryonNode& operator=(const TryonNode&) = delete;

 private:
  struct Settings {
    ResolverParams resolver;
    double tf_timeout = 0.5;  // seconds
    std::string body_frame;   // "" = the body message's frame_id (fallback "body")
  };

  // A body with its frame; the Body (and its BVH) is shared, never modified.
  struct BodyState {
    std::shared_ptr<const Body> body;
    std::string frame;
  };
  struct GarmentState {
    std::shared_ptr<const TriMesh> mesh;
    std_msgs::Header header;
  };

  void readParameters();
  void onBody(const pcl_msgs::PolygonMesh::ConstPtr& msg);
  void onGarment(const pcl_msgs::PolygonMesh::ConstPtr& msg);
  bool onResolve(virtual_tryon::ResolvePenetration::Request& req,
                 virtual_tryon::ResolvePenetration::Response& res);

  // The service's work; returns false with `error` set on bad input. May throw (caught by onResolve).
  bool resolve(const virtual_tryon::ResolvePenetration::Request& req,
               virtual_tryon::ResolvePenetration::Response& res, std::string& error);
  // Body for a request: the topic body when the request's is empty, else a Body built from the
  // request (or a cached one when its geometry is identical).
  bool requestBody(const pcl_msgs::PolygonMesh& msg, BodyState& out, std::string& error);
  bool requestGarment(const pcl_msgs::PolygonMesh& msg, TriMesh& mesh, std::string& frame,
                      std::string& error);
  // Moves garment vertices from `from` into `to` with tf2; false with `error` when no transform.
  bool transformInto(const std::string& from, const std::string& to, TriMesh& mesh,
                     std::string& error);
  // The frame a body message is in, after ~body_frame; false when they conflict.
  bool bodyFrame(const pcl_msgs::PolygonMesh& msg, std::string& frame, std::string& error) const;

  void publishMarkers(const TriMesh& body, const std::string& frame, const TriMesh* garment);

  ros::NodeHandle nh_, pnh_;
  Settings settings_;  // written once in the constructor, read-only afterwards

  tf2_ros::Buffer tf_buffer_;
  tf2_ros::TransformListener tf_listener_;

  ros::Subscriber body_sub_, garment_sub_;
  ros::Publisher fitted_pub_, markers_pub_;
  ros::ServiceServer resolve_srv_;

  std::mutex mutex_;          // guards the three members below
  BodyState topic_body_;      // latest valid body from ~body_mesh
  GarmentState topic_garment_;  // latest valid garment from ~garment_mesh
  std::shared_ptr<const Body> request_body_;  // last body built from a request, reused when equal
};

}  // namespace virtual_tryon
