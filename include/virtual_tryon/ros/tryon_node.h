// The ROS face of the penetration resolver and the drape: topics for the latest body (a mesh, or a
// raw scan meshed here) and garment (a mesh or a pattern), a service that resolves a garment
// against a body, a service and an action that drape a garment given by its cutting patterns,
// automatic fits (~auto_fit), latched results for RViz. All algorithms live in the core; this
// class only converts messages, reads parameters, transforms frames and keeps state. Its code is
// split by role: tryon_node.cpp (set-up, parameters, frames, ~resolve_penetration),
// body_input.cpp (~body_mesh, ~body_scan), auto_fit.cpp (garments in, automatic fits out),
// drape_handler.cpp (~drape, ~drape_action), publishing.cpp (latched outputs).
//
// Threading: callbacks only convert and queue. Long work (meshing a scan, checking a body,
// automatic fits) runs on one worker thread (LatestJobQueue: a newer body replaces a waiting one,
// a newer garment of the same kind replaces a waiting one; a running job finishes). Services run on
// the spinner's threads, so two requests may run at once and neither blocks the topics; the action
// runs on its own thread, and a new goal preempts (cancels) the running one. Shared state (latest
// body, garments, cached request body) is a set of pointers to immutable objects swapped under
// `mutex_`; work copies what it needs under the lock and runs without it. A Body's BVH and depth
// maps are built lazily, thread-safely, once, inside the Body.
#pragma once

#include "virtual_tryon/core/body/body.h"
#include "virtual_tryon/core/body/body_preparation.h"
#include "virtual_tryon/core/drape/drape.h"
#include "virtual_tryon/core/geometry/mesh.h"
#include "virtual_tryon/core/drape/pattern.h"
#include "virtual_tryon/core/drape/worn_garment.h"
#include "virtual_tryon/core/resolve/penetration_resolver.h"
#include "virtual_tryon/core/body/scan_meshing.h"
#include "virtual_tryon/ros/job_queue.h"
#include <virtual_tryon/BodyReport.h>
#include <virtual_tryon/Drape.h>
#include <virtual_tryon/DrapeGarmentAction.h>
#include <virtual_tryon/FitReport.h>
#include <virtual_tryon/GarmentPattern.h>

#include <actionlib/server/simple_action_server.h>
#include <sensor_msgs/PointCloud2.h>

#include <pcl_msgs/PolygonMesh.h>
#include <ros/ros.h>
#include <std_msgs/Header.h>
#include <tf2_ros/buffer.h>
#include <tf2_ros/static_transform_broadcaster.h>
#include <tf2_ros/transform_listener.h>
#include <virtual_tryon/ResolvePenetration.h>

#include <cstdint>
#include <atomic>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

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
    ScanMeshingParams scan;
    double scan_uncertainty = -1;  // m: a scanned body's uncertainty; < 0: its error's p95
    std::string world_frame = "world";  // z-up world the body frame is placed in ("" = none)
    Eigen::Vector3d up_axis{0, 1, 0};   // the body mesh's up axis (~up_axis: x, y, z, -x, -y, -z)
    MeshLimits limits;        // refused before allocation: ~max_vertices, ~max_faces
    double tf_timeout = 0.5;  // seconds
    std::string body_frame;   // "" = the body message's frame_id (fallback "body")
    bool auto_fit = false;    // fit each new body / garment on the worker and publish the result
    // m: resolving the latest garment on a later frame of the same body (topics), each vertex's
    // correction changes by at most this from the last such fit where the frame stays clean
    // (core/resolve/temporal_coherence.h); 0: off.
    double max_jitter = 0.003;
    // Resolving the latest garment on a later frame of the same body (topics): start from its input
    // moved by the last such fit's correction (warmStart: where it is 2 mm or more), resolved and
    // checked whole (resolvePenetrationsFrom);
    // a warm start that does not converge is resolved again from the input alone.
    bool warm_start = true;
  };

  // A body with its frame and what was found in it; the Body (and its BVH) is shared, never
  // modified.
  struct BodyState {
    std::shared_ptr<const Body> body;
    std::string frame;
    virtual_tryon::BodyReport report;  // report.uncertainty: fits clear the mesh by that much more
    std::vector<std::string> warnings;  // found when it was installed; repeated in every response
    ros::Time stamp;                    // of the message it came in (zero from a request)
    std::uint64_t frame_index = 0;      // 0 as installed; n: the n-th frame of that body since
    bool refitted = false;              // a frame of the body before it (Body(previous, V))
    ros::Duration frame_interval;       // a frame: its stamp less the previous frame's
    std::uint64_t series = 0;           // the body installed (1, 2, ...) this is a frame of; 0: a request's
  };
  // The last fit of the topics' garment on a frame of a topic body: the correction it made, for
  // the next frame's temporal coherence.
  struct ResolvedFrame {
    std::uint64_t series = 0, frame_index = 0;
    MatrixX3i F;
    MatrixX3d input;       // the fit's input garment
    MatrixX3d correction;  // resolved minus input
    std::shared_ptr<const GarmentConnectivity> connectivity;  // of F, for the next frame's calls
  };
  struct GarmentState {
    std::shared_ptr<const TriMesh> mesh;
    std_msgs::Header header;
  };
  struct PatternState {
    std::shared_ptr<const virtual_tryon::GarmentPattern> msg;
  };
  // What a drape needs from a request or a goal (the body and pattern are borrowed, not copied).
  struct DrapeInput {
    const pcl_msgs::PolygonMesh* body = nullptr;
    const virtual_tryon::GarmentPattern* pattern = nullptr;
    double spacing = 0, dt = 0;
    std::string collision_mode;
    std::uint32_t max_iterations = 0;
    bool skip_resolve = false;
    bool wear = false;  // auto_fit: drape as worn_ and keep it, so that the body's frames step it
  };
  // What a drape gives back (the service response and the action result have these fields).
  struct DrapeOutput {
    bool success = false;
    std::string message;
    pcl_msgs::PolygonMesh garment;
    virtual_tryon::DrapeReport report;
  };

  void readObjective(ResolverParams& p);
  void readParameters();
  // Reads the drape/ parameters over DrapeParams' defaults (drape_handler.cpp).
  static DrapeParams readDrapeParameters(const ros::NodeHandle& pnh, const ResolverParams& resolver);
  // body_input.cpp: callbacks queue; the jobs check, mesh and install the body.
  void onBody(const pcl_msgs::PolygonMesh::ConstPtr& msg);
  void onScan(const sensor_msgs::PointCloud2::ConstPtr& msg);
  void installBodyFromMesh(const pcl_msgs::PolygonMesh::ConstPtr& msg);
  void installBodyFromScan(const sensor_msgs::PointCloud2::ConstPtr& msg);
  // How the node prepares each body (prepareBody): its size limits; an inside-out body is flipped.
  BodyPreparationParams bodyPreparation() const;
  void installBody(TriMesh mesh, const std::string& frame, virtual_tryon::BodyReport report,
                   std::vector<std::string> warnings, const ros::Time& stamp);
  // A ~body_mesh message with the installed body's faces and frame is a new frame of that body:
  // installed as Body(previous, V) (no re-check, trees refitted). Returns false when the message is
  // not such a frame (the caller prepares it as a new body); true when it was installed, dropped
  // as stale (stamped before the installed frame) or unchanged.
  bool installBodyFrame(const pcl_msgs::PolygonMesh& msg, const TriMesh& mesh, const std::string& frame);
  void installState(const BodyState& state, bool newBody);  // topic body, world transform, ~body, fits
  // The header of a fit's outputs: the body's frame; a refitted body frame's stamp, else now.
  static std_msgs::Header fitHeader(const BodyState& body);
  void noteFrame(virtual_tryon::FitReport& fit, const BodyState& body) const;

  // auto_fit.cpp
  void onGarment(const pcl_msgs::PolygonMesh::ConstPtr& msg);
  void onPattern(const virtual_tryon::GarmentPattern::ConstPtr& msg);
  void postFits();  // queues a fit for each garment kind received so far (auto_fit)
  void fitGarmentMesh();
  void fitPattern();
  // The worn garment (auto_fit's drape, kept) stepped to `body`, a later frame of the body it is
  // on (WornGarment::follow), and published. False when it is not such a frame (a fresh drape is
  // due).
  bool stepWornGarment(const BodyState& body, const std::shared_ptr<const virtual_tryon::GarmentPattern>& pattern);
  bool onResolve(virtual_tryon::ResolvePenetration::Request& req,
                 virtual_tryon::ResolvePenetration::Response& res);

  // The service's work; returns false with `error` set on bad input. May throw (caught by onResolve).
  bool resolve(const virtual_tryon::ResolvePenetration::Request& req,
               virtual_tryon::ResolvePenetration::Response& res, std::string& error);
  // drape_handler.cpp
  bool onDrape(virtual_tryon::Drape::Request& req, virtual_tryon::Drape::Response& res);
  void onDrapeGoal(const virtual_tryon::DrapeGarmentGoalConstPtr& goal);
  // A drape, caught: never throws; out.success=false with the message on bad input or error.
  // `progress` (may be empty) is called every few iterations; returning false cancels.
  void drapeCaught(const DrapeInput& in, DrapeOutput& out, const DrapeProgressCallback& progress,
                   bool publish);
  // The drape's work; false with `error` on bad input, before draping. A drape that ran returns
  // true even when it failed (out.success = report.success). May throw.
  bool drape(const DrapeInput& in, DrapeOutput& out, const DrapeProgressCallback& progress,
             bool publish, std::string& error);
  // The node's drape parameters with the request's over them (zero / empty fields keep the node's);
  // false with `error` when the result is invalid.
  bool drapeParams(const DrapeInput& in, DrapeParams& params, std::string& error) const;
  // drape_handler.cpp: a pattern message converted and validated (a GarmentCode specification read
  // at `spacing` and, with a body, placed on it by the rule: placedOnBody); errors start with
  // "pattern: ". Without a body: a check only (the topic's, before the pattern is kept).
  static bool patternFromMsg(const virtual_tryon::GarmentPattern& msg, double spacing, const Body* body,
                             Pattern& pattern, bool& placedOnBody, std::string& error);

  // Body for a request: the topic body when the request's is empty, else a Body built from the
  // request (or a cached one when its geometry is identical).
  bool requestBody(const pcl_msgs::PolygonMesh& msg, BodyState& out, std::string& error);
  // The request's garment, or the topic's when the request's is empty; `header` gets its frame
  // and stamp.
  bool requestGarment(const pcl_msgs::PolygonMesh& msg, TriMesh& mesh, std_msgs::Header& header,
                      std::string& error);
  // Moves garment vertices from `from` into `to` with tf2; false with `error` when no transform.
  bool transformInto(const std::string& from, const std::string& to, const ros::Time& stamp,
                     TriMesh& mesh, std::string& error);
  // The same for a pattern's panels (their poses).
  bool transformInto(const std::string& from, const std::string& to, const ros::Time& stamp,
                     Pattern& pattern, std::string& error);
  // The transform taking points in `from` to `to` (waits up to tf_timeout); false with an error
  // naming `what` ("garment", "pattern") and both frames.
  bool lookupTransform(const std::string& from, const std::string& to, const std::string& what,
                       const ros::Time& stamp, Eigen::Isometry3d& T, std::string& error);
  // The message's frame: its own header's, else its cloud's.
  static std::string frameOf(const pcl_msgs::PolygonMesh& msg);
  // The frame a body message is in, after ~body_frame; false when they conflict.
  bool bodyFrame(const pcl_msgs::PolygonMesh& msg, std::string& frame, std::string& error) const;

  // publishing.cpp. `before` (#V by 3, may be empty): the garment's vertices before the fit, for
  // the moved-vertex points. `strain` (#V, may be empty): the fit map, the garment coloured by
  // strain (blue 0 .. red kFitMapStrain and beyond), as `tryon render` draws it.
  void publishMarkers(const TriMesh& body, const std::string& frame, const TriMesh* garment,
                      const MatrixX3d* before = nullptr, const std::vector<double>* strain = nullptr);
  void publishBody(const BodyState& body);
  // body_input.cpp: the static transform from the z-up ~world_frame to the body's frame
  // (zUpWorldFromBody with ~up_axis), so that rviz shows the body standing (REP 103).
  void publishWorldTransform(const BodyState& body);
  void publishFit(const virtual_tryon::FitReport& report, const pcl_msgs::PolygonMesh& garment);
  // Temporal coherence of a resolve of the topics' garment on a frame of a topic body (resolve()).
  std::string keepCoherent(const BodyState& body, TriMesh& garment, const MatrixX3d& input, bool converged,
                           double clearance);
  // resolve()'s resolver run: warm from the last fit when `topicFrame` and ~warm_start allow it
  // (sets `warmFrom` to that fit's frame index + 1; 0: cold).
  ResolverReport resolveFrame(const BodyState& body, TriMesh& garment, const ResolverParams& params,
                              bool topicFrame, std::uint64_t& warmFrom);
  // last_resolved_ is a fit of this garment's faces on an earlier frame of this body (call with
  // resolved_mutex_ held).
  bool lastResolvedPrecedes(const BodyState& body, const TriMesh& garment) const;

  ros::NodeHandle nh_, pnh_;
  Settings settings_;  // written once in the constructor, read-only afterwards

  tf2_ros::Buffer tf_buffer_;
  tf2_ros::TransformListener tf_listener_;
  tf2_ros::StaticTransformBroadcaster world_tf_;  // world -> body frame, sent with each new body

  ros::Subscriber body_sub_, scan_sub_, garment_sub_, pattern_sub_;
  ros::Publisher fitted_pub_, markers_pub_, body_pub_, body_report_pub_, fit_report_pub_;
  ros::ServiceServer resolve_srv_, drape_srv_;
  std::unique_ptr<actionlib::SimpleActionServer<virtual_tryon::DrapeGarmentAction>> drape_action_;

  std::mutex mutex_;          // guards the members below
  BodyState topic_body_;      // latest valid body from ~body_mesh or ~body_scan
  GarmentState topic_garment_;  // latest valid garment from ~garment_mesh
  PatternState topic_pattern_;  // latest valid pattern from ~garment_pattern
  BodyState request_body_;  // last body built from a request, reused when equal
  std::uint64_t last_scan_hash_ = 0;  // of the last scan meshed (an unchanged scan is skipped)
  std::atomic<std::uint64_t> frames_dropped_{0};  // body frames never fitted (FitReport)
  // 1 + the frame index of the installed body's latest frame that a fit took (0: none yet); reset
  // with each new body. A frame replaced before any fit took it is counted in frames_dropped_.
  std::uint64_t fit_frame_mark_ = 0;

  std::mutex publish_mutex_;  // one publisher at a time: ~fitted_garment, ~fit_report, ~markers agree

  std::uint64_t body_series_ = 0;  // bodies installed so far (BodyState::series)

  std::mutex resolved_mutex_;      // guards last_resolved_
  ResolvedFrame last_resolved_;    // the topics' garment as last resolved on a topic body

  // auto_fit's drape, worn through the body's frames (used on the worker thread only).
  struct WornState {
    std::unique_ptr<WornGarment> garment;
    std::shared_ptr<const virtual_tryon::GarmentPattern> pattern;  // the message it was draped from
    BodyState body;  // the frame it is on
  };
  WornState worn_;

  LatestJobQueue jobs_;  // last: its thread stops first when the node is destroyed
};

}  // namespace virtual_tryon
