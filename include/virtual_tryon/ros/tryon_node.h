// The ROS face of the penetration resolver and the drape: topics for the latest body and garment,
// a service that resolves a garment against a body, a service that drapes a garment given by its
// cutting patterns, latched results for RViz. All algorithms live in the core; this class only
// converts messages, reads parameters, transforms frames and keeps state. The drape service's
// code is in src/ros/drape_handler.cpp.
//
// Threading: every callback may run on any spinner thread. The shared state (latest body,
// latest garment, cached request body) is a set of pointers to immutable objects swapped under
// `mutex_`; a resolve copies what it needs under the lock and works without it, so a long resolve
// never blocks the topics and two resolves may run at once (the Body's BVH and depth maps are built
// thread-safely and cached inside the Body, so repeated drapes on one body render the maps once).
#pragma once

#include "virtual_tryon/core/body.h"
#include "virtual_tryon/core/drape.h"
#include "virtual_tryon/core/mesh.h"
#include "virtual_tryon/core/pattern.h"
#include "virtual_tryon/core/penetration_resolver.h"
#include <virtual_tryon/Drape.h>

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
    DrapeParams drape;  // its resolver part is `resolver`
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
  // Reads the drape/ parameters over DrapeParams' defaults (drape_handler.cpp).
  static DrapeParams readDrapeParameters(const ros::NodeHandle& pnh, const ResolverParams& resolver);
  void onBody(const pcl_msgs::PolygonMesh::ConstPtr& msg);
  void onGarment(const pcl_msgs::PolygonMesh::ConstPtr& msg);
  bool onResolve(virtual_tryon::ResolvePenetration::Request& req,
                 virtual_tryon::ResolvePenetration::Response& res);

  // The service's work; returns false with `error` set on bad input. May throw (caught by onResolve).
  bool resolve(const virtual_tryon::ResolvePenetration::Request& req,
               virtual_tryon::ResolvePenetration::Response& res, std::string& error);
  bool onDrape(virtual_tryon::Drape::Request& req, virtual_tryon::Drape::Response& res);
  // The drape service's work; false with `error` on bad input, before draping. A drape that ran
  // returns true even when it failed (res.success = report.success). May throw (caught by onDrape).
  bool drape(const virtual_tryon::Drape::Request& req, virtual_tryon::Drape::Response& res,
             std::string& error);

  // Body for a request: the topic body when the request's is empty, else a Body built from the
  // request (or a cached one when its geometry is identical).
  bool requestBody(const pcl_msgs::PolygonMesh& msg, BodyState& out, std::string& error);
  bool requestGarment(const pcl_msgs::PolygonMesh& msg, TriMesh& mesh, std::string& frame,
                      std::string& error);
  // Moves garment vertices from `from` into `to` with tf2; false with `error` when no transform.
  bool transformInto(const std::string& from, const std::string& to, TriMesh& mesh,
                     std::string& error);
  // The transform taking points in `from` to `to` (waits up to tf_timeout); false with an error
  // naming `what` ("garment", "pattern") and both frames.
  bool lookupTransform(const std::string& from, const std::string& to, const std::string& what,
                       Eigen::Isometry3d& T, std::string& error);
  // The frame a body message is in, after ~body_frame; false when they conflict.
  bool bodyFrame(const pcl_msgs::PolygonMesh& msg, std::string& frame, std::string& error) const;

  void publishMarkers(const TriMesh& body, const std::string& frame, const TriMesh* garment);

  ros::NodeHandle nh_, pnh_;
  Settings settings_;  // written once in the constructor, read-only afterwards

  tf2_ros::Buffer tf_buffer_;
  tf2_ros::TransformListener tf_listener_;

  ros::Subscriber body_sub_, garment_sub_;
  ros::Publisher fitted_pub_, markers_pub_;
  ros::ServiceServer resolve_srv_, drape_srv_;

  std::mutex mutex_;          // guards the three members below
  BodyState topic_body_;      // latest valid body from ~body_mesh
  GarmentState topic_garment_;  // latest valid garment from ~garment_mesh
  std::shared_ptr<const Body> request_body_;  // last body built from a request, reused when equal
};

}  // namespace virtual_tryon
