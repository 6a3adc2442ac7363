// libFuzzer target: a serialized pcl_msgs/PolygonMesh -> ros_conversions::fromMsg -> validate,
// validateBody, and back through toMsg (the round trip must give the same faces).
#include "ros_wire.h"
#include "virtual_tryon/core/body/body_preparation.h"
#include "virtual_tryon/core/geometry/mesh.h"
#include "virtual_tryon/ros/conversions.h"

#include <pcl_msgs/PolygonMesh.h>
#include <ros/serialization.h>

#include <cstdint>
#include <cstdlib>
#include <string>

namespace vt = virtual_tryon;
namespace rc = virtual_tryon::ros_conversions;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (!vt_fuzz::Wire(data, size).polygonMesh()) return 0;
  pcl_msgs::PolygonMesh msg;
  try {
    ros::serialization::IStream stream(const_cast<std::uint8_t*>(data), static_cast<std::uint32_t>(size));
    ros::serialization::deserialize(stream, msg);
  } catch (const ros::Exception&) {
    return 0;
  }
  vt::TriMesh mesh;
  std::string error;
  if (!rc::fromMsg(msg, mesh, error)) {
    if (error.empty()) std::abort();  // a failure must say why
    return 0;
  }
  const vt::MeshValidation v = vt::validate(mesh, "garment");
  const vt::MeshValidation b = vt::validateBody(mesh);
  if ((!v.ok && v.message.empty()) || (!b.ok && b.message.empty())) std::abort();
  if (v.ok) {
    // Every face index is in range: toMsg keeps them all, and they convert back unchanged.
    pcl_msgs::PolygonMesh back;
    rc::toMsg(mesh, std_msgs::Header(), back);
    vt::TriMesh again;
    if (!rc::fromMsg(back, again, error) || again.F != mesh.F || again.V.rows() != mesh.V.rows()) std::abort();
    vt::placementWarnings(mesh, again);
  }
  return 0;
}
