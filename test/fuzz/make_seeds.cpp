// Writes the binary part of the fuzz seed corpus (the text part is in test/fuzz/corpus/):
// serialized pcl_msgs/PolygonMesh and sensor_msgs/PointCloud2 messages, binary PLY and STL
// files. Everything is made here from small procedural shapes; nothing is copied from elsewhere.
// Usage: make_seeds OUTPUT_DIR   (creates polygon_mesh/, point_cloud/, mesh_io/ below it)
#include "../ros/cloud_builder.h"
#include "virtual_tryon/core/io/mesh_io.h"
#include "virtual_tryon/ros/conversions.h"

#include <pcl_msgs/PolygonMesh.h>
#include <ros/serialization.h>
#include <sensor_msgs/PointCloud2.h>
#include <sensor_msgs/PointField.h>

#include <sys/stat.h>

#include <cstdint>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <iostream>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

namespace vt = virtual_tryon;
namespace rc = virtual_tryon::ros_conversions;
using sensor_msgs::PointField;

namespace {

template <typename M>
void writeMessage(const std::string& path, const M& msg) {
  const std::uint32_t n = ros::serialization::serializationLength(msg);
  std::vector<std::uint8_t> buf(n);
  ros::serialization::OStream s(buf.data(), n);
  ros::serialization::serialize(s, msg);
  std::ofstream(path, std::ios::binary).write(reinterpret_cast<const char*>(buf.data()), n);
}

// A unit tetrahedron, outward.
vt::TriMesh tetrahedron() {
  vt::TriMesh m;
  m.V.resize(4, 3);
  m.V << 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1;
  m.F.resize(4, 3);
  m.F << 0, 2, 1, 0, 1, 3, 0, 3, 2, 1, 2, 3;
  return m;
}

using Field = virtual_tryon_test::CloudField;

// A cloud of the tetrahedron's corners laid out by `fields` (x, y, z and normal_* by name).
sensor_msgs::PointCloud2 cloud(const std::vector<Field>& fields, std::uint32_t step, std::uint32_t width,
                               std::uint32_t height, std::uint32_t rowPad) {
  const vt::TriMesh t = tetrahedron();
  return virtual_tryon_test::buildCloud(fields, step, width, height, rowPad, 0,
                                        [&](int i, const Field& f) -> std::optional<double> {
                                          const int k = f.name.back() - 'x';
                                          if (f.name.rfind("normal_", 0) == 0) return k == 2 ? 1.0 : 0.0;
                                          return t.V(i % 4, k);
                                        });
}

pcl_msgs::PolygonMesh meshMsg(const sensor_msgs::PointCloud2& c, const std::vector<std::vector<std::uint32_t>>& polys) {
  pcl_msgs::PolygonMesh m;
  m.header.frame_id = "body";
  m.cloud = c;
  for (const auto& p : polys) {
    pcl_msgs::Vertices v;
    v.vertices = p;
    m.polygons.push_back(v);
  }
  return m;
}

void copyWithPrefix(const std::string& from, const std::string& to, char prefix) {
  std::ifstream in(from, std::ios::binary);
  std::stringstream ss;
  ss << in.rdbuf();
  std::ofstream(to, std::ios::binary) << prefix << ss.str();
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 2) {
    std::cerr << "usage: make_seeds OUTPUT_DIR\n";
    return 2;
  }
  const std::string out = argv[1];
  for (const char* d : {"", "/polygon_mesh", "/point_cloud", "/mesh_io"}) ::mkdir((out + d).c_str(), 0755);

  const std::vector<Field> xyz32 = {{"x", 0, PointField::FLOAT32}, {"y", 4, PointField::FLOAT32}, {"z", 8, PointField::FLOAT32}};
  const std::vector<Field> odd64 = {{"z", 1, PointField::FLOAT64}, {"x", 9, PointField::FLOAT64}, {"y", 17, PointField::FLOAT64},
                                    {"intensity", 25, PointField::FLOAT32}};
  const std::vector<Field> normals = {{"x", 0, PointField::FLOAT32},        {"y", 4, PointField::FLOAT32},
                                      {"z", 8, PointField::FLOAT32},        {"normal_x", 16, PointField::FLOAT32},
                                      {"normal_y", 20, PointField::FLOAT32}, {"normal_z", 24, PointField::FLOAT64}};
  const std::vector<std::vector<std::uint32_t>> faces = {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}};

  writeMessage(out + "/point_cloud/xyz32", cloud(xyz32, 12, 4, 1, 0));
  writeMessage(out + "/point_cloud/odd_offsets_float64", cloud(odd64, 29, 4, 1, 0));
  writeMessage(out + "/point_cloud/normals", cloud(normals, 32, 4, 1, 0));
  writeMessage(out + "/point_cloud/organized_2x2_padded", cloud(xyz32, 12, 2, 2, 5));
  writeMessage(out + "/point_cloud/empty", sensor_msgs::PointCloud2());

  writeMessage(out + "/polygon_mesh/tetrahedron", meshMsg(cloud(xyz32, 12, 4, 1, 0), faces));
  writeMessage(out + "/polygon_mesh/tetrahedron_float64_odd", meshMsg(cloud(odd64, 29, 4, 1, 0), faces));
  writeMessage(out + "/polygon_mesh/quad_and_triangle", meshMsg(cloud(xyz32, 12, 4, 1, 0), {{0, 1, 2, 3}, {3, 2, 1}}));
  writeMessage(out + "/polygon_mesh/organized", meshMsg(cloud(normals, 32, 2, 2, 3), faces));
  writeMessage(out + "/polygon_mesh/empty", pcl_msgs::PolygonMesh());
  {
    pcl_msgs::PolygonMesh m;
    rc::toMsg(tetrahedron(), std_msgs::Header(), m);
    writeMessage(out + "/polygon_mesh/from_toMsg", m);
  }

  std::string err;
  const std::string tmp = out + "/tmp_seed";
  for (const char* ext : {".ply", ".stl"}) {
    if (!vt::writeMesh(tmp + ext, tetrahedron(), err)) {
      std::cerr << err << "\n";
      return 1;
    }
    copyWithPrefix(tmp + ext, out + "/mesh_io/tetrahedron_binary" + ext, ext[1]);
    std::remove((tmp + ext).c_str());
  }
  std::cout << "make_seeds: wrote seeds to " << out << "\n";
  return 0;
}
