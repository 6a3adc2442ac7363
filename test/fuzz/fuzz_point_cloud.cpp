// libFuzzer target: a serialized sensor_msgs/PointCloud2 -> ros_conversions::pointCloudToPoints
// (x, y, z and normals by field name, FLOAT32 / FLOAT64, any offsets, point_step, row_step).
#include "ros_wire.h"
#include "virtual_tryon/ros/conversions.h"

#include <ros/serialization.h>
#include <sensor_msgs/PointCloud2.h>

#include <cstdint>
#include <cstdlib>
#include <string>

namespace vt = virtual_tryon;
namespace rc = virtual_tryon::ros_conversions;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (!vt_fuzz::Wire(data, size).pointCloud2()) return 0;
  sensor_msgs::PointCloud2 cloud;
  try {
    ros::serialization::IStream stream(const_cast<std::uint8_t*>(data), static_cast<std::uint32_t>(size));
    ros::serialization::deserialize(stream, cloud);
  } catch (const ros::Exception&) {
    return 0;
  }
  vt::MatrixX3d V, N;
  std::string error;
  if (!rc::pointCloudToPoints(cloud, V, &N, error)) {
    if (error.empty()) std::abort();
    return 0;
  }
  const std::uint64_t n = static_cast<std::uint64_t>(cloud.width) * cloud.height;
  if (static_cast<std::uint64_t>(V.rows()) != n) std::abort();
  if (N.rows() != 0 && N.rows() != V.rows()) std::abort();
  // Without normals the points are the same.
  vt::MatrixX3d V2;
  if (!rc::pointCloudToVertices(cloud, V2, error) || V2.rows() != V.rows()) std::abort();
  for (Eigen::Index i = 0; i < V.rows(); ++i)
    for (int k = 0; k < 3; ++k)
      if (!(V(i, k) == V2(i, k)) && !(std::isnan(V(i, k)) && std::isnan(V2(i, k)))) std::abort();
  return 0;
}
