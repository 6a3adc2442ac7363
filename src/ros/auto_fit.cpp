// TryonNode's garment inputs and automatic fits. ~garment_mesh and ~garment_pattern store the
// latest garment of each kind; with ~auto_fit, a new garment, or a new body, queues a fit on the
// worker: a garment mesh is resolved, a pattern is draped, and the result goes to the latched
// outputs (so a bag replay needs no service call). A waiting fit of one kind is replaced by a newer
// one of the same kind; fits of the two kinds are kept apart, so neither is lost.
#include "virtual_tryon/ros/conversions.h"
#include "virtual_tryon/ros/pattern_conversions.h"
#include "virtual_tryon/ros/report_conversions.h"
#include "virtual_tryon/ros/tryon_node.h"

#include <algorithm>
#include <cstdio>
#include <exception>
#include <string>
#include <utility>

namespace virtual_tryon {
namespace {

namespace rc = ros_conversions;

}  // namespace

void TryonNode::onGarment(const pcl_msgs::PolygonMesh::ConstPtr& msg) {
  try {
    auto mesh = std::make_shared<TriMesh>();
    std::string error;
    if (rc::fromMsg(*msg, *mesh, error, settings_.limits)) {
      const MeshValidation v = validate(*mesh, "garment", settings_.limits);
      if (!v.ok) error = v.message;
    } else {
      error = "garment: " + error;
    }
    if (!error.empty()) {
      ROS_ERROR_STREAM("tryon_node: rejected message on " << garment_sub_.getTopic() << ": "
                                                          << error << " (keeping the previous garment)");
      return;
    }
    std_msgs::Header header = msg->header;
    header.frame_id = frameOf(*msg);
    ROS_INFO_STREAM("tryon_node: garment received (" << mesh->numVertices() << " vertices, "
                                                     << mesh->numFaces() << " faces, frame '"
                                                     << header.frame_id << "')");
    {
      std::lock_guard<std::mutex> lock(mutex_);
      topic_garment_ = GarmentState{std::move(mesh), header};
    }
    if (settings_.auto_fit) jobs_.post("fit mesh", [this] { fitGarmentMesh(); });
  } catch (const std::exception& e) {
    ROS_ERROR_STREAM("tryon_node: failed to process the garment message: " << e.what());
  }
}

void TryonNode::onPattern(const virtual_tryon::GarmentPattern::ConstPtr& msg) {
  try {
    Pattern pattern;
    std::string error;
    bool placedOnBody = false;  // no body here: a check; the drape places it
    const bool ok = patternFromMsg(*msg, settings_.drape.spacing, nullptr, pattern, placedOnBody, error);
    if (!ok) {
      ROS_ERROR_STREAM("tryon_node: rejected message on " << pattern_sub_.getTopic()
                                                          << ": " << error
                                                          << " (keeping the previous pattern)");
      return;
    }
    ROS_INFO_STREAM("tryon_node: pattern '" << pattern.name << "' received ("
                                            << pattern.panels.size() << " panels, "
                                            << pattern.seams.size() << " seams)");
    {
      std::lock_guard<std::mutex> lock(mutex_);
      topic_pattern_.msg = std::make_shared<const virtual_tryon::GarmentPattern>(*msg);
    }
    if (settings_.auto_fit) jobs_.post("fit pattern", [this] { fitPattern(); });
  } catch (const std::exception& e) {
    ROS_ERROR_STREAM("tryon_node: failed to process the pattern message: " << e.what());
  }
}

void TryonNode::postFits() {
  bool mesh = false, pattern = false;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    mesh = static_cast<bool>(topic_garment_.mesh);
    pattern = static_cast<bool>(topic_pattern_.msg);
  }
  if (mesh) jobs_.post("fit mesh", [this] { fitGarmentMesh(); });
  if (pattern) jobs_.post("fit pattern", [this] { fitPattern(); });
}

void TryonNode::fitGarmentMesh() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    if (!topic_body_.body) {
      ROS_INFO("tryon_node: auto_fit: garment mesh waiting for a body");
      return;
    }
    // A moving body: a garment stamped after the installed frame belongs to a frame to come, when
    // a body is queued or the next frame is due (within two frame intervals); that frame's install
    // fits it. Fitted on this frame, it would be corrected for a body it was not posed for (spikes
    // of 3.4 on the walk). Past that, the body has stopped: the garment is fitted on the last frame.
    // The same holds for the body as first installed when its next frame is already queued (a
    // stream whose first frame took long to check: the walk's garment frame 2 was fitted on body
    // frame 0, strain 0.72).
    const BodyState& b = topic_body_;
    if (topic_garment_.mesh && !b.stamp.isZero() && topic_garment_.header.stamp > b.stamp &&
        (jobs_.waiting("body") || topic_garment_.header.stamp <= b.stamp + b.frame_interval * 2.0)) {
      ROS_DEBUG("tryon_node: auto_fit: the garment is stamped after the body frame; waiting for its frame");
      return;
    }
  }
  // The service's path with an empty request: the latest body and garment.
  virtual_tryon::ResolvePenetration::Request req;
  virtual_tryon::ResolvePenetration::Response res;
  onResolve(req, res);
}

void TryonNode::fitPattern() {
  std::shared_ptr<const virtual_tryon::GarmentPattern> pattern;
  BodyState body;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    if (!topic_body_.body) {
      ROS_INFO("tryon_node: auto_fit: pattern waiting for a body");
      return;
    }
    pattern = topic_pattern_.msg;
    body = topic_body_;
  }
  if (!pattern) return;
  if (stepWornGarment(body, pattern)) {
    std::lock_guard<std::mutex> lock(mutex_);
    if (topic_body_.series == body.series) fit_frame_mark_ = std::max(fit_frame_mark_, body.frame_index + 1);
    return;
  }
  const pcl_msgs::PolygonMesh noBody;  // empty: the latest body
  DrapeInput in;
  in.body = &noBody;
  in.pattern = pattern.get();
  in.wear = true;
  DrapeOutput out;
  drapeCaught(in, out, nullptr, /*publish=*/true);
  if (out.success && worn_.garment && worn_.garment->worn())
    worn_.pattern = pattern;
  else
    worn_ = WornState();
}

bool TryonNode::stepWornGarment(const BodyState& body,
                                const std::shared_ptr<const virtual_tryon::GarmentPattern>& pattern) {
  if (!worn_.garment || !worn_.garment->worn() || worn_.pattern != pattern || body.series != worn_.body.series ||
      !body.refitted || body.frame_index <= worn_.body.frame_index)
    return false;
  // The time since the frame the cloth is on (frames dropped between are stepped over in one go).
  double seconds = 0;
  if (!body.stamp.isZero() && !worn_.body.stamp.isZero()) seconds = (body.stamp - worn_.body.stamp).toSec();
  if (!(seconds > 0)) seconds = body.frame_interval.toSec();
  if (!(seconds > 0)) seconds = 1.0 / 30;
  const WornFrameReport r = worn_.garment->follow(*body.body, seconds);
  virtual_tryon::FitReport fit;
  fit.kind = "drape";
  fit.header = fitHeader(body);
  fit.body = body.report;
  noteFrame(fit, body);
  fit.success = r.success;
  char head[160];
  std::snprintf(head, sizeof head, "worn garment stepped from body frame %llu to %llu (%.4f s): ",
                static_cast<unsigned long long>(worn_.body.frame_index),
                static_cast<unsigned long long>(body.frame_index), seconds);
  fit.message = head + r.message;
  fit.drape = rc::toMsg(r, worn_.garment->garment());
  fit.drape.body = body.report;
  pcl_msgs::PolygonMesh garment;
  if (r.success) {
    rc::toMsg(worn_.garment->garment(), fit.header, garment);
    worn_.body = body;
    ROS_DEBUG_STREAM("tryon_node: auto_fit: " << fit.message);
  } else {
    ROS_WARN_STREAM("tryon_node: auto_fit: " << fit.message << "; the next frame drapes afresh");
  }
  publishFit(fit, garment);
  if (r.success)
    publishMarkers(body.body->mesh(), body.frame, &worn_.garment->garment(), nullptr, &worn_.garment->vertexStrain());
  if (!r.success) worn_ = WornState();
  return true;
}

}  // namespace virtual_tryon
