// TryonNode's ~drape service (Vassilev et al. 2001 through the core's drape()) and its drape/
// parameters. The rest of the node is in tryon_node.cpp.
#include "virtual_tryon/core/drape/pattern_placement.h"
#include "virtual_tryon/core/drape/pattern_transform.h"
#include "virtual_tryon/core/io/pattern_garmentcode.h"
#include "virtual_tryon/core/io/report_summary.h"
#include "virtual_tryon/ros/conversions.h"
#include "virtual_tryon/ros/pattern_conversions.h"
#include "virtual_tryon/ros/report_conversions.h"
#include "virtual_tryon/ros/tryon_node.h"

#include <algorithm>
#include <chrono>
#include <cstdint>
#include <exception>
#include <limits>
#include <sstream>
#include <string>
#include <utility>

namespace virtual_tryon {
namespace {

namespace rc = ros_conversions;

template <typename T>
std::string show(const T& v) {
  std::ostringstream o;
  o << std::boolalpha << v;
  return o.str();
}

// Reads ~name into field(p) when the parameter is set. The new value is checked by the core's
// validateDrapeParams with every other field as read so far (all valid), so a problem it reports
// is this value's; then the value is refused with a warning quoting the core and the previous
// value (the default) is kept.
template <typename T, typename Field>
void readChecked(const ros::NodeHandle& pnh, const std::string& name, DrapeParams& p, Field field) {
  if (!pnh.hasParam(name)) return;
  T value{};
  if (!pnh.getParam(name, value)) {
    ROS_WARN_STREAM("tryon_node: ~" << name << " has the wrong type; using " << show(field(p)));
    return;
  }
  DrapeParams trial = p;
  field(trial) = value;
  const std::string problem = validateDrapeParams(trial);
  if (!problem.empty()) {
    ROS_WARN_STREAM("tryon_node: ~" << name << " = " << show(value) << " is invalid: " << problem
                                    << "; using " << show(field(p)));
    return;
  }
  field(p) = value;
}

// Logs the drape's progress at most every two seconds; cancels the drape when ROS shuts down.
class ProgressLog {
 public:
  bool operator()(const DrapeProgress& p) {
    const auto now = std::chrono::steady_clock::now();
    if (now - last_ >= std::chrono::seconds(2)) {
      last_ = now;
      ROS_INFO("tryon_node: drape: iteration %d (%s), %.1f s, largest seam gap %.4f m, "
               "max speed %.3f m/s",
               p.iteration, p.sewing ? "sewing" : "draping", p.seconds, p.seam_gap, p.max_speed);
    }
    return ros::ok();
  }

 private:
  std::chrono::steady_clock::time_point last_ = std::chrono::steady_clock::now();
};

}  // namespace

namespace {

// The Drape request and the DrapeGarment goal carry the same fields; so do the response and the
// result.
template <typename Request, typename Input>
void borrowInput(const Request& r, Input& in) {
  in.body = &r.body;
  in.pattern = &r.pattern;
  in.spacing = r.spacing;
  in.dt = r.dt;
  in.collision_mode = r.collision_mode;
  in.max_iterations = r.max_iterations;
  in.skip_resolve = r.skip_resolve;
}

template <typename Output, typename Response>
void moveOutput(Output& out, Response& r) {
  r.success = out.success;
  r.message = std::move(out.message);
  r.garment = std::move(out.garment);
  r.report = std::move(out.report);
}

void logDrape(const DrapeResult& report) {
  ROS_INFO("tryon_node: drape: %d iterations (%d sewing), %.3f s, %zu vertices, penetrating "
           "vertices %zu before / %zu after the resolver%s, %d of %d seams open, %zu boundary loops for "
           "%zu openings, largest strain %.3f, %s",
           report.iterations, report.sew_iterations, report.seconds_total, report.vertices,
           report.penetrating_before_resolve, report.penetrating_after,
           report.resolver_run ? "" : " (not run)", report.seams_open, report.seams_total,
           report.boundary_loops, report.openings, report.strain_max_final,
           report.converged ? "converged" : "NOT converged");
  if (!report.converged) ROS_WARN_STREAM("tryon_node: " << report.message);
  for (const std::string& w : report.warnings) ROS_WARN_STREAM("tryon_node: drape: " << w);
}

}  // namespace

bool TryonNode::patternFromMsg(const virtual_tryon::GarmentPattern& msg, double spacing, const Body* body,
                               Pattern& pattern, bool& placedOnBody, std::string& error) {
  placedOnBody = false;
  if (!msg.garmentcode_json.empty()) {
    if (!msg.panels.empty() || !msg.seams.empty()) {
      error = "pattern: garmentcode_json and panels / seams are both set: send one or the other";
      return false;
    }
    GarmentCodeReadParams rp;
    rp.spacing = spacing;
    GarmentCodeReport report;
    if (!parseGarmentCodeJson(msg.garmentcode_json, rp, pattern, report, error)) {
      error = "pattern: garmentcode_json: " + error;
      return false;
    }
    if (pattern.name.empty()) pattern.name = msg.name.empty() ? "garmentcode" : msg.name;
    for (const std::string& w : report.warnings) ROS_WARN_STREAM("tryon_node: pattern: " << w);
    if (msg.use_placement) {
      const geometry_msgs::Transform& t = msg.placement;
      geometry_msgs::Pose pose;
      pose.position.x = t.translation.x;
      pose.position.y = t.translation.y;
      pose.position.z = t.translation.z;
      pose.orientation = t.rotation;
      Eigen::Isometry3d T;
      if (!rc::poseToIsometry(pose, T, error)) {
        error = "pattern: placement: " + error;
        return false;
      }
      transformPattern(T, pattern);
    } else if (body) {
      BodyPlacementParams bp;
      bp.scale_to_height = msg.scale_to_height;
      const BodyPlacement placement = placePatternOnBody(*body, pattern, bp);
      ROS_INFO_STREAM("tryon_node: pattern: placement: " << placement.rule);
      placedOnBody = true;
    }
    return true;
  }
  if (!rc::fromMsg(msg, pattern, error)) {
    error = "pattern: " + error;
    return false;
  }
  error = validatePattern(pattern);
  if (!error.empty()) {
    error = "pattern: " + error;
    return false;
  }
  return true;
}

DrapeParams TryonNode::readDrapeParameters(const ros::NodeHandle& pnh,
                                           const ResolverParams& resolver) {
  DrapeParams p;
  p.resolver = resolver;
  const std::string problem = validateDrapeParams(p);
  if (!problem.empty())  // the core's defaults; cannot happen unless the core changes
    ROS_ERROR_STREAM("tryon_node: the default drape parameters are invalid: " << problem);

  readChecked<double>(pnh, "drape/spacing", p, [](DrapeParams& q) -> double& { return q.spacing; });
  std::string mode;
  if (pnh.getParam("drape/collision_mode", mode) && !rc::parseCollisionMode(mode, p.mode))
    ROS_WARN_STREAM("tryon_node: ~drape/collision_mode = '" << mode
                                                            << "' is invalid (\"image\" or \"object\"); using "
                                                            << rc::collisionModeName(p.mode));
  readChecked<double>(pnh, "drape/tol", p, [](DrapeParams& q) -> double& { return q.collision.tol; });
  readChecked<int>(pnh, "drape/map_size", p, [](DrapeParams& q) -> int& { return q.collision.map_size; });
  readChecked<double>(pnh, "drape/friction", p, [](DrapeParams& q) -> double& { return q.collision.friction; });
  readChecked<double>(pnh, "drape/reflection", p, [](DrapeParams& q) -> double& { return q.collision.reflection; });
  readChecked<double>(pnh, "drape/density", p, [](DrapeParams& q) -> double& { return q.cloth.density; });
  readChecked<double>(pnh, "drape/k_structural", p, [](DrapeParams& q) -> double& { return q.cloth.k_structural; });
  readChecked<double>(pnh, "drape/k_shear", p, [](DrapeParams& q) -> double& { return q.cloth.k_shear; });
  readChecked<double>(pnh, "drape/k_flexion", p, [](DrapeParams& q) -> double& { return q.cloth.k_flexion; });
  readChecked<double>(pnh, "drape/k_seam", p, [](DrapeParams& q) -> double& { return q.cloth.k_seam; });
  readChecked<double>(pnh, "drape/damping_rate", p, [](DrapeParams& q) -> double& { return q.cloth.damping_rate; });
  readChecked<double>(pnh, "drape/stretch_threshold", p,
                      [](DrapeParams& q) -> double& { return q.cloth.stretch_threshold; });
  readChecked<int>(pnh, "drape/weld_relax_passes", p, [](DrapeParams& q) -> int& { return q.cloth.weld_relax_passes; });
  readChecked<double>(pnh, "drape/dt", p, [](DrapeParams& q) -> double& { return q.dt; });
  readChecked<bool>(pnh, "drape/clamp_dt", p, [](DrapeParams& q) -> bool& { return q.clamp_dt; });
  readChecked<int>(pnh, "drape/max_iterations", p, [](DrapeParams& q) -> int& { return q.max_iterations; });
  readChecked<double>(pnh, "drape/settle_speed", p, [](DrapeParams& q) -> double& { return q.settle_speed; });
  readChecked<double>(pnh, "drape/max_strain", p, [](DrapeParams& q) -> double& { return q.max_strain; });
  readChecked<bool>(pnh, "drape/resolve", p, [](DrapeParams& q) -> bool& { return q.resolve; });
  readChecked<double>(pnh, "drape/resolve_rest_strain", p, [](DrapeParams& q) -> double& { return q.resolve_rest_strain; });
  readChecked<double>(pnh, "drape/time_budget", p, [](DrapeParams& q) -> double& { return q.time_budget; });
  ROS_INFO("tryon_node: drape: spacing %g m, %s space, tol %g m, map_size %d, friction %g, "
           "reflection %g, density %g kg/m^2, k %g/%g/%g/%g N/m (structural/shear/flexion/seam), "
           "damping %g 1/s, stretch threshold %g, dt %g s%s, max %d iterations, settle %g m/s, "
           "resolve %s, time budget %g s",
           p.spacing, rc::collisionModeName(p.mode).c_str(), p.collision.tol, p.collision.map_size,
           p.collision.friction, p.collision.reflection, p.cloth.density, p.cloth.k_structural,
           p.cloth.k_shear, p.cloth.k_flexion, p.cloth.k_seam, p.cloth.damping_rate,
           p.cloth.stretch_threshold, p.dt, p.clamp_dt ? " (clamp_dt: clamp to the bound)" : "",
           p.max_iterations, p.settle_speed, p.resolve ? "on" : "off", p.time_budget);
  return p;
}

bool TryonNode::onDrape(virtual_tryon::Drape::Request& req, virtual_tryon::Drape::Response& res) {
  DrapeInput in;
  borrowInput(req, in);
  DrapeOutput out;
  ProgressLog log;
  drapeCaught(in, out, [&log](const DrapeProgress& p) { return log(p); }, /*publish=*/true);
  moveOutput(out, res);
  return true;  // the call itself worked; the response says why it failed
}

void TryonNode::onDrapeGoal(const virtual_tryon::DrapeGarmentGoalConstPtr& goal) {
  DrapeInput in;
  borrowInput(*goal, in);
  ProgressLog log;
  auto progress = [this, &log](const DrapeProgress& p) {
    virtual_tryon::DrapeGarmentFeedback fb;
    fb.iteration = static_cast<std::uint32_t>(std::max(0, p.iteration));
    fb.sewing = p.sewing;
    fb.seam_gap = p.seam_gap;
    fb.kinetic_energy = p.kinetic_energy;
    fb.max_speed = p.max_speed;
    fb.seconds = p.seconds;
    drape_action_->publishFeedback(fb);
    // A cancel, a newer goal (which preempts this one) or shutdown stops the drape.
    return log(p) && !drape_action_->isPreemptRequested();
  };
  DrapeOutput out;
  drapeCaught(in, out, progress, /*publish=*/true);
  virtual_tryon::DrapeGarmentResult result;
  moveOutput(out, result);
  if (result.report.cancelled || drape_action_->isPreemptRequested())
    drape_action_->setPreempted(result, result.message);
  else if (result.success)
    drape_action_->setSucceeded(result, result.message);
  else
    drape_action_->setAborted(result, result.message);
}

void TryonNode::drapeCaught(const DrapeInput& in, DrapeOutput& out,
                            const DrapeProgressCallback& progress, bool publish) {
  std::string error;
  try {
    if (drape(in, out, progress, publish, error)) return;
  } catch (const std::exception& e) {
    error = std::string("internal error: ") + e.what();
  } catch (...) {
    error = "internal error (unknown exception)";
  }
  out = DrapeOutput();
  out.success = false;
  out.message = error;
  ROS_WARN_STREAM("tryon_node: drape failed: " << error);
  if (publish) {
    virtual_tryon::FitReport fit;
    fit.kind = "drape";
    fit.success = false;
    fit.message = error;
    publishFit(fit, out.garment);
  }
}

bool TryonNode::drapeParams(const DrapeInput& req, DrapeParams& params, std::string& error) const {
  // Zero / empty request fields keep the node's.
  params = settings_.drape;
  if (req.spacing != 0) params.spacing = req.spacing;
  if (req.dt != 0) params.dt = req.dt;
  if (!req.collision_mode.empty() && !rc::parseCollisionMode(req.collision_mode, params.mode)) {
    error = "collision_mode '" + req.collision_mode +
            "' is unknown (\"image\", \"object\", or \"\" for ~drape/collision_mode)";
    return false;
  }
  if (req.max_iterations > 0)
    params.max_iterations = static_cast<int>(
        std::min<std::uint32_t>(req.max_iterations, std::numeric_limits<int>::max()));
  if (req.skip_resolve) params.resolve = false;
  error = validateDrapeParams(params);
  return error.empty();
}

bool TryonNode::drape(const DrapeInput& req, DrapeOutput& res, const DrapeProgressCallback& progress,
                      bool publish, std::string& error) {
  DrapeParams params;
  Pattern pattern;
  BodyState body;
  bool placedOnBody = false;
  if (!drapeParams(req, params, error) || !requestBody(*req.body, body, error) ||
      !patternFromMsg(*req.pattern, params.spacing, body.body.get(), pattern, placedOnBody, error))
    return false;
  const std::string& patternFrame = req.pattern->header.frame_id;
  if (!placedOnBody && !patternFrame.empty() && patternFrame != body.frame &&
      !transformInto(patternFrame, body.frame, req.pattern->header.stamp, pattern, error))
    return false;

  params.resolver.body_uncertainty = body.report.uncertainty;
  const int rendersBefore = body.body->depthMapRenders();
  TriMesh garment;
  DrapeResult report;
  if (req.wear && params.mode == CollisionMode::ImageSpace) {
    // auto_fit: worn, so that the body's later frames step this cloth instead of draping afresh.
    WornGarmentParams wp;
    wp.drape = params;
    worn_ = WornState();
    worn_.garment = std::make_unique<WornGarment>(wp);
    report = worn_.garment->dress(*body.body, pattern, progress);
    garment = worn_.garment->garment();
    worn_.body = body;
  } else {
    report = virtual_tryon::drape(*body.body, pattern, params, garment, progress);
  }
  const bool rendered = body.body->depthMapRenders() > rendersBefore;

  res.success = report.success;
  res.report = rc::toMsg(report, params.mode);
  res.report.body = body.report;
  for (const std::string& w : body.warnings) res.report.warnings.push_back(w);
  res.message = drapeMessage(report, body.warnings, params.mode, rendered);
  virtual_tryon::FitReport fit;
  fit.kind = "drape";
  fit.body = body.report;
  noteFrame(fit, body);
  if (!report.success) {
    ROS_WARN_STREAM("tryon_node: drape failed: " << report.message);
    if (publish) {
      fit.success = false;
      fit.message = res.message;
      fit.drape = res.report;
      publishFit(fit, res.garment);
    }
    return true;
  }
  const std_msgs::Header header = fitHeader(body);
  rc::toMsg(garment, header, res.garment);
  logDrape(report);

  if (publish) {
    fit.header = header;
    fit.success = true;
    fit.message = res.message;
    fit.drape = res.report;
    publishFit(fit, res.garment);
    publishMarkers(body.body->mesh(), body.frame, &garment,
                   report.draped_vertices.rows() == garment.V.rows() ? &report.draped_vertices
                                                                      : nullptr,
                   &report.vertex_strain);
  }
  return true;
}

}  // namespace virtual_tryon
