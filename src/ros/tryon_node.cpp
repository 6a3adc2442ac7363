#include "virtual_tryon/ros/tryon_node.h"

#include "virtual_tryon/core/drape/pattern_transform.h"
#include "virtual_tryon/core/geometry/rigid_transform.h"
#include "virtual_tryon/core/io/report_summary.h"
#include "virtual_tryon/core/resolve/temporal_coherence.h"
#include "virtual_tryon/ros/conversions.h"
#include "virtual_tryon/ros/report_conversions.h"

#include <tf2/exceptions.h>
#include <tf2_eigen/tf2_eigen.h>
#include <visualization_msgs/MarkerArray.h>

#include <cmath>
#include <map>
#include <cstdio>
#include <exception>
#include <sstream>
#include <utility>

namespace virtual_tryon {
namespace {

namespace rc = ros_conversions;

// A mesh message with no polygons and no points means "use the latest from the topic".
bool isEmpty(const pcl_msgs::PolygonMesh& msg) {
  return msg.polygons.empty() &&
         static_cast<std::uint64_t>(msg.cloud.width) * msg.cloud.height == 0;
}

bool sameMesh(const TriMesh& a, const TriMesh& b) {
  return a.V.rows() == b.V.rows() && a.F.rows() == b.F.rows() && a.V == b.V && a.F == b.F;
}

// Converts and validates; `what` ("body", "garment") prefixes the error. `validation` (may be
// null) receives validate()'s result.
bool meshFromMsg(const pcl_msgs::PolygonMesh& msg, const std::string& what, const MeshLimits& limits,
                 TriMesh& mesh, std::string& error, MeshValidation* validation = nullptr) {
  if (!rc::fromMsg(msg, mesh, error, limits)) {
    error = what + ": " + error;
    return false;
  }
  // A body is checked further (and flipped if inside out) by prepareBody, without validating again.
  MeshValidation v = validate(mesh, what, limits);
  if (!v.ok) {
    error = v.message;
    return false;
  }
  if (!v.message.empty()) ROS_WARN_STREAM("tryon_node: " << v.message);
  if (validation) *validation = std::move(v);
  return true;
}

double readDouble(const ros::NodeHandle& pnh, const std::string& name, double def, bool positive) {
  double v = def;
  pnh.param(name, v, def);
  if (!std::isfinite(v) || v < 0 || (positive && v == 0)) {
    ROS_WARN_STREAM("tryon_node: ~" << name << " = " << v << " is invalid (must be "
                                    << (positive ? "> 0" : ">= 0") << "); using " << def);
    v = def;
  }
  return v;
}

int readCount(const ros::NodeHandle& pnh, const std::string& name, int def) {
  int v = def;
  pnh.param(name, v, def);
  if (v < 1) {
    ROS_WARN_STREAM("tryon_node: ~" << name << " = " << v << " is invalid (must be >= 1); using "
                                    << def);
    v = def;
  }
  return v;
}

std::string seconds(double s) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%g", s);
  return buf;
}

std::string stampText(const ros::Time& t) {
  char buf[48];
  std::snprintf(buf, sizeof buf, "%u.%03u", t.sec, t.nsec / 1000000u);
  return buf;
}

}  // namespace

TryonNode::TryonNode(ros::NodeHandle nh, ros::NodeHandle pnh)
    : nh_(std::move(nh)),
      pnh_(std::move(pnh)),
      tf_listener_(tf_buffer_),
      jobs_([](const std::string& what) {
        ROS_ERROR_STREAM("tryon_node: background job failed: " << what);
      }) {
  readParameters();
  fitted_pub_ = pnh_.advertise<pcl_msgs::PolygonMesh>("fitted_garment", 1, /*latch=*/true);
  markers_pub_ = pnh_.advertise<visualization_msgs::MarkerArray>("markers", 1, /*latch=*/true);
  body_pub_ = pnh_.advertise<pcl_msgs::PolygonMesh>("body", 1, /*latch=*/true);
  body_report_pub_ = pnh_.advertise<virtual_tryon::BodyReport>("body_report", 1, /*latch=*/true);
  fit_report_pub_ = pnh_.advertise<virtual_tryon::FitReport>("fit_report", 4, /*latch=*/true);
  // Queues of a few messages: a bag replayed fast must not drop a body or a garment.
  // The callbacks only queue, so a deep subscriber queue costs nothing: frames of a moving body that
  // come too fast are dropped by the node's own queue, which counts them (FitReport.frames_dropped),
  // not by the transport, which would drop them unseen.
  body_sub_ = pnh_.subscribe("body_mesh", 16, &TryonNode::onBody, this);
  scan_sub_ = pnh_.subscribe("body_scan", 2, &TryonNode::onScan, this);
  garment_sub_ = pnh_.subscribe("garment_mesh", 16, &TryonNode::onGarment, this);
  pattern_sub_ = pnh_.subscribe("garment_pattern", 4, &TryonNode::onPattern, this);
  resolve_srv_ = pnh_.advertiseService("resolve_penetration", &TryonNode::onResolve, this);
  drape_srv_ = pnh_.advertiseService("drape", &TryonNode::onDrape, this);
  drape_action_ = std::make_unique<actionlib::SimpleActionServer<virtual_tryon::DrapeGarmentAction>>(
      pnh_, "drape_action", [this](const virtual_tryon::DrapeGarmentGoalConstPtr& g) { onDrapeGoal(g); },
      /*auto_start=*/false);
  drape_action_->start();
  ROS_INFO_STREAM("tryon_node: ready; services " << resolve_srv_.getService() << ", "
                                                 << drape_srv_.getService() << ", action "
                                                 << pnh_.resolveName("drape_action") << ", topics "
                                                 << body_sub_.getTopic() << ", " << scan_sub_.getTopic()
                                                 << ", " << garment_sub_.getTopic() << ", "
                                                 << pattern_sub_.getTopic() << "; auto_fit "
                                                 << (settings_.auto_fit ? "on" : "off"));
}

std::string TryonNode::frameOf(const pcl_msgs::PolygonMesh& msg) {
  return msg.header.frame_id.empty() ? msg.cloud.header.frame_id : msg.header.frame_id;
}

// ~objective: "smooth" (default: the rounds, then the shape relaxation) or "paper" (the rounds
// alone); ~relaxation/max_sweeps, local_max_sweeps, strain_limit, local_rotations, polish_strain
// and fine_polish_strain tune the relaxation.
void TryonNode::readObjective(ResolverParams& p) {
  const ResolverParams d;
  std::string objective;
  pnh_.param("objective", objective, std::string("smooth"));
  if (objective == "paper") {
    p.objective = ResolverObjective::Paper;
  } else {
    if (objective != "smooth")
      ROS_WARN_STREAM("tryon_node: ~objective must be 'smooth' or 'paper', got '" << objective
                                                                                 << "'; using 'smooth'");
    p.objective = ResolverObjective::Smooth;
  }
  p.relaxation.max_sweeps = readCount(pnh_, "relaxation/max_sweeps", d.relaxation.max_sweeps);
  p.relaxation.local_max_sweeps = readCount(pnh_, "relaxation/local_max_sweeps", d.relaxation.local_max_sweeps);
  p.relaxation.strain_limit = readDouble(pnh_, "relaxation/strain_limit", d.relaxation.strain_limit, false);
  pnh_.param("relaxation/local_rotations", p.relaxation.local_rotations, d.relaxation.local_rotations);
  p.relaxation.polish_strain = readDouble(pnh_, "relaxation/polish_strain", d.relaxation.polish_strain, false);
  if (p.relaxation.polish_strain == 0) p.relaxation.polish_passes = 0;
  p.relaxation.fine_polish_strain =
      readDouble(pnh_, "relaxation/fine_polish_strain", d.relaxation.fine_polish_strain, false);
}

void TryonNode::readParameters() {
  const ResolverParams d;
  ResolverParams& p = settings_.resolver;
  p.clearance = readDouble(pnh_, "clearance", d.clearance, false);
  p.clearance_fraction = readDouble(pnh_, "clearance_fraction", d.clearance_fraction, true);
  p.max_iterations = readCount(pnh_, "max_iterations", d.max_iterations);
  p.stall_iterations = readCount(pnh_, "stall_iterations", d.stall_iterations);
  pnh_.param("check_inside", p.check_inside, d.check_inside);
  pnh_.param("push_out_inside", p.push_out_inside, d.push_out_inside);
  p.time_budget = readDouble(pnh_, "time_budget", d.time_budget, false);
  readObjective(p);
  settings_.tf_timeout = readDouble(pnh_, "tf_timeout", 0.5, false);
  pnh_.param("body_frame", settings_.body_frame, std::string());
  pnh_.param("auto_fit", settings_.auto_fit, false);
  settings_.max_jitter = readDouble(pnh_, "max_jitter", settings_.max_jitter, false);
  pnh_.param("warm_start", settings_.warm_start, settings_.warm_start);
  pnh_.param("warm_local_relaxation", p.warm_local_relaxation, d.warm_local_relaxation);
  const ScanMeshingParams sd;
  settings_.scan.voxel_size = readDouble(pnh_, "scan/voxel_size", sd.voxel_size, false);
  settings_.scan.normal_neighbours = readCount(pnh_, "scan/normal_neighbours", sd.normal_neighbours);
  pnh_.param("scan/depth", settings_.scan.depth, sd.depth);
  pnh_.param("scan/max_auto_depth", settings_.scan.max_auto_depth, sd.max_auto_depth);
  pnh_.param("scan/uncertainty", settings_.scan_uncertainty, -1.0);
  pnh_.param("world_frame", settings_.world_frame, std::string("world"));
  std::string up;
  pnh_.param("up_axis", up, std::string("y"));
  const std::map<std::string, Eigen::Vector3d> axes = {
      {"x", Eigen::Vector3d::UnitX()}, {"y", Eigen::Vector3d::UnitY()}, {"z", Eigen::Vector3d::UnitZ()},
      {"-x", -Eigen::Vector3d::UnitX()}, {"-y", -Eigen::Vector3d::UnitY()}, {"-z", -Eigen::Vector3d::UnitZ()}};
  if (axes.count(up)) settings_.up_axis = axes.at(up);
  else ROS_WARN_STREAM("tryon_node: ~up_axis '" << up << "' is not one of x, y, z, -x, -y, -z; using y");
  if (!std::isfinite(settings_.scan_uncertainty)) {
    ROS_WARN("tryon_node: ~scan/uncertainty is not finite; using -1 (the scan's error)");
    settings_.scan_uncertainty = -1;
  }
  const std::string scanProblem = validateScanMeshingParams(settings_.scan);
  if (!scanProblem.empty()) {
    ROS_WARN_STREAM("tryon_node: ~scan/ parameters are invalid: " << scanProblem
                                                                 << "; using the defaults");
    settings_.scan = sd;
  }
  settings_.limits.max_vertices = static_cast<std::size_t>(
      readCount(pnh_, "max_vertices", static_cast<int>(settings_.limits.max_vertices)));
  settings_.limits.max_faces = static_cast<std::size_t>(
      readCount(pnh_, "max_faces", static_cast<int>(settings_.limits.max_faces)));
  settings_.drape = readDrapeParameters(pnh_, settings_.resolver);
  settings_.drape.limits = settings_.limits;
}

bool TryonNode::bodyFrame(const pcl_msgs::PolygonMesh& msg, std::string& frame,
                          std::string& error) const {
  const std::string own = frameOf(msg);
  const std::string& param = settings_.body_frame;
  if (!param.empty() && !own.empty() && own != param) {
    error = "body is in frame '" + own + "' but ~body_frame is '" + param +
            "'; send the body in '" + param + "' or leave ~body_frame empty";
    return false;
  }
  frame = !param.empty() ? param : (!own.empty() ? own : std::string("body"));
  return true;
}

bool TryonNode::onResolve(virtual_tryon::ResolvePenetration::Request& req,
                          virtual_tryon::ResolvePenetration::Response& res) {
  std::string error;
  try {
    if (resolve(req, res, error)) return true;
  } catch (const std::exception& e) {
    error = std::string("internal error: ") + e.what();
  } catch (...) {
    error = "internal error (unknown exception)";
  }
  res.success = false;
  res.message = error;
  ROS_WARN_STREAM("tryon_node: resolve_penetration failed: " << error);
  virtual_tryon::FitReport fit;
  fit.kind = "resolve";
  fit.success = false;
  fit.message = error;
  publishFit(fit, res.garment);
  return true;  // the call itself worked; the response says why it failed
}

bool TryonNode::requestBody(const pcl_msgs::PolygonMesh& msg, BodyState& out, std::string& error) {
  if (isEmpty(msg)) {
    std::lock_guard<std::mutex> lock(mutex_);
    if (!topic_body_.body) {
      error = "the request has no body and none has been received on " + body_sub_.getTopic() +
              " yet";
      return false;
    }
    out = topic_body_;
    fit_frame_mark_ = std::max(fit_frame_mark_, topic_body_.frame_index + 1);
    return true;
  }
  TriMesh mesh;
  MeshValidation validation;
  if (!meshFromMsg(msg, "body", settings_.limits, mesh, error, &validation) ||
      !bodyFrame(msg, out.frame, error))
    return false;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    if (topic_body_.body && sameMesh(topic_body_.body->mesh(), mesh)) {
      out.body = topic_body_.body;
      out.report = topic_body_.report;
      out.warnings = topic_body_.warnings;
      return true;
    }
    if (request_body_.body && sameMesh(request_body_.body->mesh(), mesh)) {
      out.body = request_body_.body;
      out.report = request_body_.report;
      out.warnings = request_body_.warnings;
      return true;
    }
  }
  // Validated above: checked (and flipped if inside out) without validating again.
  BodyPreparation prep = prepareBody(std::move(mesh), std::move(validation), bodyPreparation());
  if (!prep.ok) {
    error = prep.error;
    return false;
  }
  out.report = rc::toMsg(prep.check, "mesh");
  out.warnings = std::move(prep.warnings);
  for (const std::string& w : out.warnings) ROS_WARN_STREAM("tryon_node: request: " << w);
  out.body = std::make_shared<const Body>(std::move(prep.mesh));
  std::lock_guard<std::mutex> lock(mutex_);
  request_body_ = out;
  return true;
}

bool TryonNode::requestGarment(const pcl_msgs::PolygonMesh& msg, TriMesh& mesh,
                               std_msgs::Header& header, std::string& error) {
  if (isEmpty(msg)) {
    std::lock_guard<std::mutex> lock(mutex_);
    if (!topic_garment_.mesh) {
      error = "the request has no garment and none has been received on " +
              garment_sub_.getTopic() + " yet";
      return false;
    }
    mesh = *topic_garment_.mesh;
    header = topic_garment_.header;
    return true;
  }
  header = msg.header;
  header.frame_id = frameOf(msg);
  return meshFromMsg(msg, "garment", settings_.limits, mesh, error);
}

bool TryonNode::lookupTransform(const std::string& from, const std::string& to,
                                const std::string& what, const ros::Time& stamp,
                                Eigen::Isometry3d& T, std::string& error) {
  try {
    // At the message's stamp (a zero stamp: the latest), waiting up to tf_timeout for it.
    T = tf2::transformToEigen(
        tf_buffer_.lookupTransform(to, from, stamp, ros::Duration(settings_.tf_timeout)));
  } catch (const tf2::ExtrapolationException& e) {
    error = "the transform from the " + what + "'s frame '" + from + "' to the body's frame '" + to +
            "' is stale: none at the " + what + "'s stamp " + stampText(stamp) + " s within " +
            seconds(settings_.tf_timeout) + " s: " + e.what();
    return false;
  } catch (const tf2::TransformException& e) {
    error = "no transform from the " + what + "'s frame '" + from + "' to the body's frame '" + to +
            "' within " + seconds(settings_.tf_timeout) + " s: " + e.what();
    return false;
  }
  return true;
}

bool TryonNode::transformInto(const std::string& from, const std::string& to, const ros::Time& stamp,
                              TriMesh& mesh, std::string& error) {
  Eigen::Isometry3d T;
  if (!lookupTransform(from, to, "garment", stamp, T, error)) return false;
  transformMesh(T, mesh);
  return true;
}

bool TryonNode::transformInto(const std::string& from, const std::string& to, const ros::Time& stamp,
                              Pattern& pattern, std::string& error) {
  Eigen::Isometry3d T;
  if (!lookupTransform(from, to, "pattern", stamp, T, error)) return false;
  transformPattern(T, pattern);
  return true;
}

bool TryonNode::resolve(const virtual_tryon::ResolvePenetration::Request& req,
                        virtual_tryon::ResolvePenetration::Response& res, std::string& error) {
  BodyState body;
  TriMesh garment;
  std_msgs::Header garmentHeader;
  if (!requestBody(req.body, body, error) || !requestGarment(req.garment, garment, garmentHeader, error))
    return false;
  const std::string& garmentFrame = garmentHeader.frame_id;
  if (!garmentFrame.empty() && garmentFrame != body.frame &&
      !transformInto(garmentFrame, body.frame, garmentHeader.stamp, garment, error))
    return false;

  const std::string warnings =
      warningSuffix(inputWarnings(body.warnings, body.body->mesh(), garment, settings_.limits));
  ResolverParams params = settings_.resolver;
  if (req.clearance > 0) params.clearance = req.clearance;
  if (req.max_iterations > 0) params.max_iterations = static_cast<int>(req.max_iterations);
  params.body_uncertainty = body.report.uncertainty;

  const MatrixX3d before = garment.V;
  const bool topicFrame = isEmpty(req.body) && isEmpty(req.garment) && body.series != 0;
  std::uint64_t warmFrom = 0;
  const ResolverReport report = resolveFrame(body, garment, params, topicFrame, warmFrom);
  std::string coherence = topicFrame ? keepCoherent(body, garment, before, report.converged, report.clearance)
                                     : std::string();
  if (warmFrom > 0) coherence = "; warm start from frame " + std::to_string(warmFrom - 1) + coherence;

  const std_msgs::Header header = fitHeader(body);
  rc::toMsg(garment, header, res.garment);
  res.report = rc::toMsg(report);
  res.report.body = body.report;
  res.success = report.converged;
  res.message = resolveSummary(report) + coherence + warnings;
  ROS_INFO("tryon_node: resolve: crossings before %zu+%zu, after %zu+%zu (garment+body edges), "
           "%d iterations, %.3f s, %s",
           report.garment_edge_crossings_before, report.body_edge_crossings_before,
           report.garment_edge_crossings_after, report.body_edge_crossings_after,
           report.iterations, report.seconds_total, report.converged ? "converged" : "NOT converged");
  if (!report.converged) ROS_WARN_STREAM("tryon_node: " << res.message);

  virtual_tryon::FitReport fit;
  fit.header = header;
  fit.kind = "resolve";
  fit.success = res.success;
  fit.message = res.message;
  fit.body = body.report;
  fit.resolve = res.report;
  noteFrame(fit, body);
  publishFit(fit, res.garment);
  TriMesh input;  // the garment as it came, for the fit map's edge strain
  input.V = before;
  input.F = garment.F;
  const std::vector<double> strain = vertexEdgeStrain(input, garment.V);
  publishMarkers(body.body->mesh(), body.frame, &garment, &before, &strain);
  return true;
}

// The topics' garment resolved on a later frame of the body it was last resolved on: where a
// vertex's correction jumped since then, the clean position nearest to the last correction
// (limitCorrectionChange). Remembers this fit's correction for the next frame. Returns what it did
// for the message ("" when it did nothing).
std::string TryonNode::keepCoherent(const BodyState& body, TriMesh& garment, const MatrixX3d& input, bool converged,
                                    double clearance) {
  std::lock_guard<std::mutex> lock(resolved_mutex_);
  std::string said;
  if (converged && settings_.max_jitter > 0 && lastResolvedPrecedes(body, garment)) {
    CoherenceParams cp;
    cp.max_change = settings_.max_jitter;
    cp.min_clearance = 0.5 * clearance;
    cp.connectivity = last_resolved_.connectivity;
    const CoherenceReport c = limitCorrectionChange(*body.body, garment, input, last_resolved_.correction, cp);
    if (c.candidates > 0) {
      std::ostringstream o;
      o << "; temporal coherence: " << c.candidates << " vertices' corrections changed by more than "
        << settings_.max_jitter << " m since frame " << last_resolved_.frame_index << ", " << c.limited
        << " brought within it (largest change " << c.change_before << " -> " << c.change_after << " m)";
      if (c.strain_refusals > 0)
        o << ", " << c.strain_refusals << " moves refused for straining an edge past " << cp.max_strain;
      if (c.forced_by_input > 0)
        o << ", " << c.forced_by_input << " of those left over forced by the input (its last correction lies inside "
          << "the body deeper than the limit)";
      said = o.str();
    }
  }
  if (converged) {
    // the connectivity of these faces: the frame before's when it had the same faces
    std::shared_ptr<const GarmentConnectivity> connectivity =
        last_resolved_.F.rows() == garment.F.rows() && last_resolved_.F == garment.F && last_resolved_.connectivity
            ? last_resolved_.connectivity
            : garmentConnectivity(garment);
    last_resolved_ = ResolvedFrame{body.series, body.frame_index, garment.F, input, garment.V - input, connectivity};
  } else {
    last_resolved_ = ResolvedFrame();
  }
  return said;
}

bool TryonNode::lastResolvedPrecedes(const BodyState& body, const TriMesh& garment) const {
  return last_resolved_.series == body.series && last_resolved_.frame_index < body.frame_index &&
         last_resolved_.F.rows() == garment.F.rows() && last_resolved_.F == garment.F &&
         last_resolved_.correction.rows() == garment.V.rows();
}

ResolverReport TryonNode::resolveFrame(const BodyState& body, TriMesh& garment, const ResolverParams& params,
                                       bool topicFrame, std::uint64_t& warmFrom) {
  warmFrom = 0;
  PreviousFrame previous;
  ResolverParams frameParams = params;
  if (topicFrame) {
    std::lock_guard<std::mutex> lock(resolved_mutex_);
    if (lastResolvedPrecedes(body, garment)) {
      frameParams.connectivity = last_resolved_.connectivity;
      if (settings_.warm_start) {
        previous = PreviousFrame{last_resolved_.input, last_resolved_.correction};
        warmFrom = last_resolved_.frame_index + 1;
      }
    }
  }
  FrameStart start = FrameStart::Cold;
  const ResolverReport report = virtual_tryon::resolveFrame(*body.body, garment, previous, frameParams,
                                                            defaultWarmStartMin(params), &start);
  if (start != FrameStart::Warm) warmFrom = 0;
  return report;
}

}  // namespace virtual_tryon
