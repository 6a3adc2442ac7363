// TryonNode's latched outputs: ~body and ~body_report (the body in use), ~fitted_garment and
// ~fit_report (each fit, with the same header), ~markers (RViz: the body semi-transparent, the
// fitted garment, and the garment vertices the fit moved as points coloured by how far).
#include "virtual_tryon/ros/conversions.h"
#include "virtual_tryon/ros/tryon_node.h"

#include <visualization_msgs/MarkerArray.h>

#include <algorithm>
#include <cmath>
#include <vector>

namespace virtual_tryon {
namespace {

namespace rc = ros_conversions;

std_msgs::ColorRGBA rgba(float r, float g, float b, float a) {
  std_msgs::ColorRGBA c;
  c.r = r;
  c.g = g;
  c.b = b;
  c.a = a;
  return c;
}

// The fit map's colours: hue from blue (no strain) to red (kFitMapStrain and beyond), as the
// renderer's lookup table (render/fit_render.cpp).
constexpr double kFitMapStrain = 0.15;
std_msgs::ColorRGBA strainColour(double strain) {
  const double t = std::min(1.0, std::max(0.0, strain / kFitMapStrain));
  const double h = 4.0 * (1.0 - t);  // hue in sixths of the circle: 4 blue, 2 green, 0 red
  const double s = 0.85, v = 0.95, c = v * s;
  const double x = c * (1.0 - std::abs(std::fmod(h, 2.0) - 1.0)), m = v - c;
  double r = 0, g = 0, b = 0;
  if (h >= 3) g = x, b = c;
  else if (h >= 2) g = c, b = x;
  else if (h >= 1) r = x, g = c;
  else r = c, g = x;
  return rgba(static_cast<float>(r + m), static_cast<float>(g + m), static_cast<float>(b + m), 1.0f);
}

visualization_msgs::Marker deleteMarker(const std::string& frame, const std::string& ns, int id) {
  visualization_msgs::Marker del;
  del.header.frame_id = frame;
  del.ns = ns;
  del.id = id;
  del.action = visualization_msgs::Marker::DELETE;
  return del;
}

}  // namespace

void TryonNode::publishMarkers(const TriMesh& body, const std::string& frame, const TriMesh* garment,
                               const MatrixX3d* before, const std::vector<double>* strain) {
  visualization_msgs::MarkerArray array;
  array.markers.push_back(
      rc::toTriangleListMarker(body, frame, "body", 0, rgba(0.6f, 0.6f, 0.6f, 0.4f)));
  if (!garment) {  // a new body: the garment fitted to the previous one no longer applies
    array.markers.push_back(deleteMarker(frame, "garment", 1));
    array.markers.push_back(deleteMarker(frame, "moved", 2));
  } else {
    std::vector<std_msgs::ColorRGBA> colours;
    if (strain && strain->size() == static_cast<std::size_t>(garment->V.rows()))
      for (double e : *strain) colours.push_back(strainColour(e));
    array.markers.push_back(rc::toTriangleListMarker(*garment, frame, "garment", 1,
                                                     rgba(0.15f, 0.45f, 0.85f, 1.0f),
                                                     colours.empty() ? nullptr : &colours));
    if (before && before->rows() == garment->V.rows()) {
      // Moved vertices as points, blue (barely moved) to red (the largest move of this fit).
      const Eigen::VectorXd d = (garment->V - *before).rowwise().norm();
      const double dmax = d.size() ? d.maxCoeff() : 0.0;
      visualization_msgs::Marker pts;
      pts.header.frame_id = frame;
      pts.ns = "moved";
      pts.id = 2;
      pts.type = visualization_msgs::Marker::POINTS;
      pts.action = visualization_msgs::Marker::ADD;
      pts.pose.orientation.w = 1.0;
      pts.scale.x = pts.scale.y = 0.006;  // point size, m
      pts.color = rgba(1, 1, 1, 1);
      for (Eigen::Index i = 0; i < d.size(); ++i) {
        if (!(d(i) > 0)) continue;
        geometry_msgs::Point p;
        p.x = garment->V(i, 0);
        p.y = garment->V(i, 1);
        p.z = garment->V(i, 2);
        pts.points.push_back(p);
        const float t = dmax > 0 ? static_cast<float>(std::min(1.0, d(i) / dmax)) : 0.0f;
        pts.colors.push_back(rgba(t, 0.2f * (1 - t), 1.0f - t, 1.0f));
      }
      if (pts.points.empty()) array.markers.push_back(deleteMarker(frame, "moved", 2));
      else array.markers.push_back(pts);
    } else {
      array.markers.push_back(deleteMarker(frame, "moved", 2));
    }
  }
  std::lock_guard<std::mutex> lock(publish_mutex_);
  markers_pub_.publish(array);
}

void TryonNode::publishBody(const BodyState& body) {
  std_msgs::Header header;
  header.frame_id = body.frame;
  header.stamp = ros::Time::now();
  pcl_msgs::PolygonMesh msg;
  rc::toMsg(body.body->mesh(), header, msg);
  {
    std::lock_guard<std::mutex> lock(publish_mutex_);
    body_pub_.publish(msg);
    body_report_pub_.publish(body.report);
  }
  publishMarkers(body.body->mesh(), body.frame, nullptr);
}

void TryonNode::publishFit(const virtual_tryon::FitReport& report,
                           const pcl_msgs::PolygonMesh& garment) {
  std::lock_guard<std::mutex> lock(publish_mutex_);
  // The garment first, then its report: a listener that waits for the report has both.
  if (!garment.polygons.empty()) fitted_pub_.publish(garment);
  fit_report_pub_.publish(report);
}

}  // namespace virtual_tryon
