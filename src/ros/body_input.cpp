// TryonNode's body inputs: ~body_mesh (a meshed scan) and ~body_scan (a raw scan, meshed here with
// PCL). The callbacks only queue; the worker converts, prepares the body in the core (prepareBody:
// validated once, checked, an inverted body flipped), and installs it. An unchanged body or scan costs a
// comparison. The rest of the node is in tryon_node.cpp.
#include "virtual_tryon/core/body/body_preparation.h"
#include "virtual_tryon/core/body/scan_meshing.h"
#include "virtual_tryon/core/geometry/rigid_transform.h"
#include "virtual_tryon/ros/conversions.h"
#include "virtual_tryon/ros/report_conversions.h"
#include "virtual_tryon/ros/tryon_node.h"

#include <geometry_msgs/TransformStamped.h>
#include <tf2_eigen/tf2_eigen.h>

#include <algorithm>
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <string>
#include <utility>

namespace virtual_tryon {
namespace {

namespace rc = ros_conversions;

// FNV-1a over the geometry of a scan: its layout and its bytes (not its header).
std::uint64_t scanHash(const sensor_msgs::PointCloud2& c) {
  std::uint64_t h = 1469598103934665603ull;
  auto mix = [&h](const void* p, std::size_t n) {
    const auto* b = static_cast<const unsigned char*>(p);
    for (std::size_t i = 0; i < n; ++i) h = (h ^ b[i]) * 1099511628211ull;
  };
  const std::uint32_t dims[4] = {c.width, c.height, c.point_step, c.row_step};
  mix(dims, sizeof dims);
  for (const auto& f : c.fields) {
    mix(f.name.data(), f.name.size());
    mix(&f.offset, sizeof f.offset);
    mix(&f.datatype, sizeof f.datatype);
  }
  mix(c.data.data(), c.data.size());
  return h;
}

}  // namespace

BodyPreparationParams TryonNode::bodyPreparation() const {
  BodyPreparationParams params;
  params.limits = settings_.limits;
  params.policy = InsideOutPolicy::Flip;
  return params;
}

void TryonNode::onBody(const pcl_msgs::PolygonMesh::ConstPtr& msg) {
  // A body still waiting is replaced by this one (the queue keeps the latest): a frame never fitted.
  if (jobs_.post("body", [this, msg] { installBodyFromMesh(msg); })) ++frames_dropped_;
}

void TryonNode::onScan(const sensor_msgs::PointCloud2::ConstPtr& msg) {
  jobs_.post("body", [this, msg] { installBodyFromScan(msg); });
}

void TryonNode::installBodyFromMesh(const pcl_msgs::PolygonMesh::ConstPtr& msg) {
  TriMesh mesh;
  std::string frame, error;
  if (!rc::fromMsg(*msg, mesh, error, settings_.limits)) error = "body: " + error;
  else if (bodyFrame(*msg, frame, error)) {
    if (installBodyFrame(*msg, mesh, frame)) return;
    BodyPreparation prep = prepareBody(std::move(mesh), bodyPreparation());
    if (prep.ok) {
      installBody(std::move(prep.mesh), frame, rc::toMsg(prep.check, "mesh"), std::move(prep.warnings),
                  msg->header.stamp);
      return;
    }
    error = prep.error;
  }
  ROS_ERROR_STREAM("tryon_node: rejected message on " << body_sub_.getTopic() << ": " << error
                                                      << " (keeping the previous body)");
}

void TryonNode::installBodyFromScan(const sensor_msgs::PointCloud2::ConstPtr& msg) {
  const std::uint64_t hash = scanHash(*msg);
  std::string frame = settings_.body_frame.empty() ? msg->header.frame_id : settings_.body_frame;
  if (frame.empty()) frame = "body";
  std::string error;
  if (!settings_.body_frame.empty() && !msg->header.frame_id.empty() &&
      msg->header.frame_id != settings_.body_frame) {
    error = "scan is in frame '" + msg->header.frame_id + "' but ~body_frame is '" +
            settings_.body_frame + "'";
  }
  {
    std::lock_guard<std::mutex> lock(mutex_);
    if (error.empty() && hash == last_scan_hash_ && topic_body_.body &&
        topic_body_.report.source == "scan") {
      ROS_DEBUG("tryon_node: scan on %s unchanged; nothing to do", scan_sub_.getTopic().c_str());
      return;
    }
  }
  MatrixX3d points, normals;
  if (error.empty() && rc::pointCloudToPoints(*msg, points, &normals, error, settings_.limits)) {
    const ScanMeshingResult scan = meshScan(points, normals, settings_.scan);
    if (!scan.success) {
      error = "scan: " + scan.message;
    } else {
      BodyPreparation prep = prepareBody(scan.mesh, bodyPreparation());
      if (prep.ok) {
        virtual_tryon::BodyReport report = rc::toMsg(prep.check, "scan");
        report.scan_points = static_cast<std::uint32_t>(scan.input_points);
        report.scan_points_used = static_cast<std::uint32_t>(scan.points_after_downsampling);
        report.normals_estimated = scan.normals_estimated;
        report.seconds_meshing = scan.seconds_total;
        report.poisson_depth = static_cast<std::uint32_t>(scan.depth);
        report.noise_sigma = scan.noise.sigma;
        report.scan_error_median = scan.error.median;
        report.scan_error_p95 = scan.error.p95;
        report.scan_error_max = scan.error.max;
        report.scan_error_share_over_2mm = scan.error.share_over_2mm;
        report.uncertainty = settings_.scan_uncertainty >= 0 ? settings_.scan_uncertainty : scan.error.p95;
        ROS_INFO("tryon_node: scan meshed: %zu points (%zu used), %s, depth %d, %.2f s; noise %.2f mm; "
                 "points to mesh: median %.2f, 95%% %.2f, max %.2f mm, %.1f%% beyond 2 mm; fits clear "
                 "the mesh by their clearance + %.2f mm (%s)",
                 static_cast<std::size_t>(scan.input_points),
                 static_cast<std::size_t>(scan.points_after_downsampling),
                 scan.normals_estimated ? "normals estimated" : "normals from the scan", scan.depth,
                 scan.seconds_total, 1e3 * scan.noise.sigma, 1e3 * scan.error.median, 1e3 * scan.error.p95,
                 1e3 * scan.error.max, 100.0 * scan.error.share_over_2mm, 1e3 * report.uncertainty,
                 settings_.scan_uncertainty >= 0 ? "~scan/uncertainty" : "the scan's 95% error");
        {
          std::lock_guard<std::mutex> lock(mutex_);
          last_scan_hash_ = hash;
        }
        installBody(std::move(prep.mesh), frame, std::move(report), std::move(prep.warnings), msg->header.stamp);
        return;
      }
      // An unusable mesh is named as the body's; an inside-out one says so itself.
      error = prep.check.ok ? prep.error : "body: " + prep.error;
    }
  }
  ROS_ERROR_STREAM("tryon_node: rejected message on " << scan_sub_.getTopic() << ": " << error
                                                      << " (keeping the previous body)");
}

bool TryonNode::installBodyFrame(const pcl_msgs::PolygonMesh& msg, const TriMesh& mesh, const std::string& frame) {
  BodyState previous;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    previous = topic_body_;
  }
  // Only a mesh body whose faces came as they are (not flipped) has the message's own faces.
  if (!previous.body || previous.frame != frame || previous.report.source != "mesh" || previous.report.flipped ||
      previous.body->mesh().V.rows() != mesh.V.rows() || previous.body->mesh().F != mesh.F)
    return false;
  if (!mesh.V.allFinite()) return false;  // the full path names what is wrong
  if (!previous.stamp.isZero() && !msg.header.stamp.isZero() && msg.header.stamp < previous.stamp) {
    ++frames_dropped_;
    ROS_WARN_THROTTLE(5.0, "tryon_node: body frame stamped %.3f s is older than the installed %.3f s: dropped "
                      "(%llu body frames not fitted so far)", msg.header.stamp.toSec(), previous.stamp.toSec(),
                      static_cast<unsigned long long>(frames_dropped_.load()));
    return true;
  }
  if (previous.body->mesh().V == mesh.V) {
    ROS_DEBUG("tryon_node: body on %s unchanged; nothing to do", body_sub_.getTopic().c_str());
    return true;
  }
  const auto t0 = std::chrono::steady_clock::now();
  BodyState state = previous;
  state.body = std::make_shared<const Body>(*previous.body, mesh.V);
  // The faces were checked with the first frame; a frame turned inside out (or flat) is a new body.
  if (!(state.body->signedVolume() > 0)) return false;
  state.report.signed_volume = state.body->signedVolume();
  state.stamp = msg.header.stamp;
  state.frame_interval = previous.stamp.isZero() ? ros::Duration(0) : msg.header.stamp - previous.stamp;
  state.frame_index = previous.frame_index + 1;
  state.refitted = true;
  char summary[160];
  std::snprintf(summary, sizeof summary, "frame %llu of the body: faces and lists reused, %s (%.1f ms)",
                static_cast<unsigned long long>(state.frame_index),
                state.body->bvhRefitted() ? "trees refitted" : "trees built when first needed",
                std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count());
  state.report.summary = summary;
  ROS_DEBUG_STREAM("tryon_node: " << state.report.summary);
  installState(state, /*newBody=*/false);
  return true;
}

void TryonNode::installBody(TriMesh mesh, const std::string& frame, virtual_tryon::BodyReport report,
                            std::vector<std::string> warnings, const ros::Time& stamp) {
  BodyState state;
  state.warnings = std::move(warnings);
  state.body = std::make_shared<const Body>(std::move(mesh));  // BVH and maps: lazily, when needed
  state.frame = frame;
  state.report = std::move(report);
  state.stamp = stamp;
  for (const std::string& w : state.warnings) ROS_WARN_STREAM("tryon_node: " << w);
  ROS_INFO_STREAM("tryon_node: body from " << state.report.source << " in frame '" << frame
                                           << "': " << state.report.summary);
  installState(state, /*newBody=*/true);
}

void TryonNode::installState(const BodyState& state, bool newBody) {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    // The frame this one replaces was installed for nothing if no fit took it (auto_fit).
    if (!newBody && settings_.auto_fit && topic_body_.body && topic_body_.frame_index + 1 > fit_frame_mark_)
      ++frames_dropped_;
    if (newBody) fit_frame_mark_ = 0;
    topic_body_ = state;
    if (newBody) topic_body_.series = ++body_series_;
  }
  // The world placement follows the body as installed, not each frame (it would sway with it).
  if (newBody) publishWorldTransform(state);
  publishBody(state);
  if (settings_.auto_fit) postFits();
}

std_msgs::Header TryonNode::fitHeader(const BodyState& body) {
  std_msgs::Header header;
  header.frame_id = body.frame;
  // A frame of a moving body: its own stamp, so that each fit pairs with its frame. A body as first
  // installed (or from a request): the time of the fit, so that successive fits of one body (a
  // resolve and a drape) are told apart.
  header.stamp = body.refitted && !body.stamp.isZero() ? body.stamp : ros::Time::now();
  return header;
}

void TryonNode::noteFrame(virtual_tryon::FitReport& fit, const BodyState& body) const {
  fit.body_frame_index = body.frame_index;
  fit.body_refitted = body.refitted;
  fit.frames_dropped = frames_dropped_.load();
}

void TryonNode::publishWorldTransform(const BodyState& state) {
  if (settings_.world_frame.empty() || settings_.world_frame == state.frame) return;
  geometry_msgs::TransformStamped t =
      tf2::eigenToTransform(zUpWorldFromBody(state.body->mesh(), settings_.up_axis));
  t.header.stamp = ros::Time::now();
  t.header.frame_id = settings_.world_frame;
  t.child_frame_id = state.frame;
  world_tf_.sendTransform(t);
}

}  // namespace virtual_tryon
