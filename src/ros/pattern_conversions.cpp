#include "virtual_tryon/ros/pattern_conversions.h"

#include <cmath>
#include <cstdint>
#include <limits>
#include <sstream>

namespace virtual_tryon {
namespace ros_conversions {
namespace {

std::string panelName(const std::string& name, std::size_t index) {
  return "panel '" + name + "' (index " + std::to_string(index) + ")";
}

bool toIndex(std::uint32_t v, const char* field, std::size_t seam, int& out, std::string& error) {
  if (v > static_cast<std::uint32_t>(std::numeric_limits<int>::max())) {
    error = "seam " + std::to_string(seam) + ": " + field + " = " + std::to_string(v) +
            " is out of range";
    return false;
  }
  out = static_cast<int>(v);
  return true;
}

std::uint32_t fromIndex(int v) { return v < 0 ? 0u : static_cast<std::uint32_t>(v); }

}  // namespace

bool poseToIsometry(const geometry_msgs::Pose& pose, Eigen::Isometry3d& out, std::string& error) {
  const auto& q = pose.orientation;
  const auto& p = pose.position;
  if (!std::isfinite(q.x) || !std::isfinite(q.y) || !std::isfinite(q.z) || !std::isfinite(q.w)) {
    error = "pose orientation is not a finite quaternion";
    return false;
  }
  Eigen::Quaterniond quat(q.w, q.x, q.y, q.z);
  const double norm = quat.norm();
  if (!(norm >= 1e-9) || !std::isfinite(norm)) {
    std::ostringstream o;
    o << "pose orientation (x " << q.x << ", y " << q.y << ", z " << q.z << ", w " << q.w
      << ") is not a rotation: its norm " << norm
      << " is (close to) zero; use w = 1 for no rotation";
    error = o.str();
    return false;
  }
  if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z)) {
    error = "pose position is not finite";
    return false;
  }
  quat.coeffs() /= norm;
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = quat.toRotationMatrix();
  T.translation() = Eigen::Vector3d(p.x, p.y, p.z);
  out = T;
  return true;
}

geometry_msgs::Pose isometryToPose(const Eigen::Isometry3d& T) {
  Eigen::Quaterniond q(T.linear());
  q.normalize();
  if (q.w() < 0) q.coeffs() = -q.coeffs();
  geometry_msgs::Pose pose;
  pose.position.x = T.translation().x();
  pose.position.y = T.translation().y();
  pose.position.z = T.translation().z();
  pose.orientation.x = q.x();
  pose.orientation.y = q.y();
  pose.orientation.z = q.z();
  pose.orientation.w = q.w();
  return pose;
}

bool fromMsg(const GarmentPattern& msg, Pattern& pattern, std::string& error) {
  Pattern out;
  out.name = msg.name;
  out.panels.reserve(msg.panels.size());
  for (std::size_t i = 0; i < msg.panels.size(); ++i) {
    const Panel& pm = msg.panels[i];
    if (pm.outline_u.size() != pm.outline_v.size()) {
      error = panelName(pm.name, i) + ": outline_u has " + std::to_string(pm.outline_u.size()) +
              " values but outline_v has " + std::to_string(pm.outline_v.size()) +
              " (one u and one v per outline point)";
      return false;
    }
    PatternPanel panel;
    panel.name = pm.name;
    panel.outline.resize(static_cast<Eigen::Index>(pm.outline_u.size()), 2);
    for (std::size_t k = 0; k < pm.outline_u.size(); ++k) {
      panel.outline(static_cast<Eigen::Index>(k), 0) = pm.outline_u[k];
      panel.outline(static_cast<Eigen::Index>(k), 1) = pm.outline_v[k];
    }
    std::string poseError;
    if (!poseToIsometry(pm.pose, panel.placement.pose, poseError)) {
      error = panelName(pm.name, i) + ": " + poseError;
      return false;
    }
    panel.placement.wrap_radius = pm.wrap_radius;
    out.panels.push_back(std::move(panel));
  }
  out.seams.reserve(msg.seams.size());
  for (std::size_t i = 0; i < msg.seams.size(); ++i) {
    const Seam& sm = msg.seams[i];
    PatternSeam s;
    if (!toIndex(sm.panel_a, "panel_a", i, s.a.panel, error) ||
        !toIndex(sm.a_from, "a_from", i, s.a.from, error) ||
        !toIndex(sm.a_to, "a_to", i, s.a.to, error) ||
        !toIndex(sm.panel_b, "panel_b", i, s.b.panel, error) ||
        !toIndex(sm.b_from, "b_from", i, s.b.from, error) ||
        !toIndex(sm.b_to, "b_to", i, s.b.to, error) || !toIndex(sm.stage, "stage", i, s.stage, error))
      return false;
    out.seams.push_back(s);
  }
  pattern = std::move(out);
  return true;
}

GarmentPattern toMsg(const Pattern& pattern, const std_msgs::Header& header) {
  GarmentPattern msg;
  msg.header = header;
  msg.name = pattern.name;
  msg.panels.reserve(pattern.panels.size());
  for (const PatternPanel& p : pattern.panels) {
    Panel pm;
    pm.name = p.name;
    pm.outline_u.resize(static_cast<std::size_t>(p.outline.rows()));
    pm.outline_v.resize(static_cast<std::size_t>(p.outline.rows()));
    for (Eigen::Index k = 0; k < p.outline.rows(); ++k) {
      pm.outline_u[static_cast<std::size_t>(k)] = p.outline(k, 0);
      pm.outline_v[static_cast<std::size_t>(k)] = p.outline(k, 1);
    }
    pm.pose = isometryToPose(p.placement.pose);
    pm.wrap_radius = p.placement.wrap_radius;
    msg.panels.push_back(std::move(pm));
  }
  msg.seams.reserve(pattern.seams.size());
  for (const PatternSeam& s : pattern.seams) {
    Seam sm;
    sm.panel_a = fromIndex(s.a.panel);
    sm.a_from = fromIndex(s.a.from);
    sm.a_to = fromIndex(s.a.to);
    sm.panel_b = fromIndex(s.b.panel);
    sm.b_from = fromIndex(s.b.from);
    sm.b_to = fromIndex(s.b.to);
    sm.stage = fromIndex(s.stage);
    msg.seams.push_back(sm);
  }
  return msg;
}

}  // namespace ros_conversions
}  // namespace virtual_tryon
