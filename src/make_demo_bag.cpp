// make_demo_bag: writes the project's demo scene into a small bag that replays it into tryon_node:
//   ~body_scan       sensor_msgs/PointCloud2  the synthetic scan of the procedural body (x, y, z only)
//   ~garment_mesh    pcl_msgs/PolygonMesh     a waist tube placed with penetrations
//   ~garment_pattern virtual_tryon/GarmentPattern  a pattern from config/patterns/procedural/
// Usage: make_demo_bag OUT.bag PATTERN.yaml [--node NAME]   (NAME: /tryon_node)
// Deterministic: the same build writes the same messages.
#include "virtual_tryon/core/scenes/demo_scene.h"
#include "virtual_tryon/core/drape/pattern.h"
#include "virtual_tryon/core/io/pattern_yaml.h"
#include "virtual_tryon/ros/conversions.h"
#include "virtual_tryon/ros/pattern_conversions.h"

#include <rosbag/bag.h>
#include <sensor_msgs/PointCloud2.h>
#include <sensor_msgs/PointField.h>

#include <cstring>
#include <exception>
#include <iostream>
#include <string>

namespace vt = virtual_tryon;

namespace {

sensor_msgs::PointCloud2 scanCloud(const vt::MatrixX3d& P, const std_msgs::Header& header) {
  sensor_msgs::PointCloud2 c;
  c.header = header;
  c.height = 1;
  c.width = static_cast<std::uint32_t>(P.rows());
  const char* names[3] = {"x", "y", "z"};
  for (int k = 0; k < 3; ++k) {
    sensor_msgs::PointField f;
    f.name = names[k];
    f.offset = 4 * k;
    f.datatype = sensor_msgs::PointField::FLOAT32;
    f.count = 1;
    c.fields.push_back(f);
  }
  c.point_step = 12;
  c.row_step = c.point_step * c.width;
  c.is_bigendian = false;
  c.is_dense = true;
  c.data.resize(static_cast<std::size_t>(c.row_step));
  for (Eigen::Index i = 0; i < P.rows(); ++i)
    for (int k = 0; k < 3; ++k) {
      const float v = static_cast<float>(P(i, k));
      std::memcpy(&c.data[12 * i + 4 * k], &v, 4);
    }
  return c;
}

}  // namespace

int main(int argc, char** argv) {
  try {
    if (argc < 3) {
      std::cerr << "usage: make_demo_bag OUT.bag PATTERN.yaml [--node NAME]\n";
      return 2;
    }
    const std::string out = argv[1], patternPath = argv[2];
    std::string node = "/tryon_node";
    if (argc >= 5 && std::string(argv[3]) == "--node") node = argv[4];

    vt::Pattern pattern;
    std::string error;
    if (!vt::readPatternYaml(patternPath, pattern, error)) {
      std::cerr << "make_demo_bag: " << error << "\n";
      return 2;
    }
    const vt::DemoScene scene = vt::makeDemoScene();

    const ros::Time t0(1700000000, 0);  // a fixed start, so that the bag is the same every time
    std_msgs::Header header;
    header.frame_id = "body";
    rosbag::Bag bag(out, rosbag::bagmode::Write);
    header.stamp = t0;
    bag.write(node + "/body_scan", t0, scanCloud(scene.scan, header));
    pcl_msgs::PolygonMesh garment;
    header.stamp = t0 + ros::Duration(0.5);
    vt::ros_conversions::toMsg(scene.garment, header, garment);
    bag.write(node + "/garment_mesh", header.stamp, garment);
    header.stamp = t0 + ros::Duration(1.0);
    bag.write(node + "/garment_pattern", header.stamp,
              vt::ros_conversions::toMsg(pattern, header));
    bag.close();
    std::cout << "make_demo_bag: wrote " << out << ": scan of " << scene.scan.rows()
              << " points, garment of " << scene.garment.numVertices() << " vertices, pattern '"
              << pattern.name << "' (" << pattern.panels.size() << " panels)\n";
    return 0;
  } catch (const std::exception& e) {
    std::cerr << "make_demo_bag: " << e.what() << "\n";
    return 1;
  }
}
