#include "../cloud_builder.h"
#include "virtual_tryon/ros/conversions.h"

#include <gtest/gtest.h>

#include <sensor_msgs/PointField.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <functional>
#include <optional>
#include <string>
#include <vector>

namespace vt = virtual_tryon;
namespace rc = virtual_tryon::ros_conversions;
using sensor_msgs::PointField;

namespace {

using Field = virtual_tryon_test::CloudField;

// The points written into every cloud below; float32 fields hold the float-rounded values.
const double kPoints[][3] = {
    {0.1, -2.5, 3.25}, {1e-3, 0.0, -7.125}, {42.0, 0.3333333333333333, -0.2}, {-1.5, 2.0, 1e5}};
constexpr int kNumPoints = 4;

// Writes the point `kPoints[i]` into a buffer laid out by `fields` (x, y, z by name; any other
// field gets a recognisable junk pattern).
sensor_msgs::PointCloud2 makeCloud(const std::vector<Field>& fields, std::uint32_t pointStep,
                                   std::uint32_t width = kNumPoints, std::uint32_t height = 1,
                                   std::uint32_t rowPadding = 0) {
  return virtual_tryon_test::buildCloud(fields, pointStep, width, height, rowPadding, 0xAB,
                                        [](int i, const Field& f) -> std::optional<double> {
                                          const int k = f.name == "x" ? 0 : f.name == "y" ? 1 : f.name == "z" ? 2 : -1;
                                          if (k < 0) return std::nullopt;
                                          return kPoints[i % kNumPoints][k];
                                        });
}

double expected(int i, int k, bool isDouble) {
  const double v = kPoints[i % kNumPoints][k];
  return isDouble ? v : static_cast<double>(static_cast<float>(v));
}

const std::vector<Field> kXyz32 = {{"x", 0, PointField::FLOAT32},
                                   {"y", 4, PointField::FLOAT32},
                                   {"z", 8, PointField::FLOAT32}};

struct CloudCase {
  std::string name;
  std::function<sensor_msgs::PointCloud2()> make;
  bool ok;
  std::string errorContains;          // when !ok
  std::array<bool, 3> isDouble{};     // when ok: which of x, y, z are FLOAT64
};

}  // namespace

TEST(PointCloudToVertices, Table) {
  const std::vector<CloudCase> cases = {
      {"float32 packed", [] { return makeCloud(kXyz32, 12); }, true, "", {false, false, false}},
      {"float64 packed",
       [] {
         return makeCloud({{"x", 0, PointField::FLOAT64}, {"y", 8, PointField::FLOAT64},
                           {"z", 16, PointField::FLOAT64}},
                          24);
       },
       true, "", {true, true, true}},
      {"mixed types, odd offsets with padding",
       [] {
         return makeCloud({{"x", 1, PointField::FLOAT32}, {"y", 5, PointField::FLOAT64},
                           {"z", 17, PointField::FLOAT32}},
                          23);
       },
       true, "", {false, true, false}},
      {"PointXYZRGBNormal-like with extra fields in scrambled order",
       [] {
         return makeCloud({{"normal_x", 16, PointField::FLOAT32},
                           {"z", 8, PointField::FLOAT32},
                           {"rgb", 32, PointField::FLOAT32},
                           {"x", 0, PointField::FLOAT32},
                           {"normal_y", 20, PointField::FLOAT32},
                           {"y", 4, PointField::FLOAT32},
                           {"curvature", 36, PointField::FLOAT32}},
                          48);
       },
       true, "", {false, false, false}},
      {"organised 2 x 2 with row padding",
       [] { return makeCloud(kXyz32, 16, 2, 2, 8); }, true, "", {false, false, false}},
      {"missing z",
       [] {
         return makeCloud({{"x", 0, PointField::FLOAT32}, {"y", 4, PointField::FLOAT32}}, 12);
       },
       false, "'z'"},
      {"integer x",
       [] {
         return makeCloud({{"x", 0, PointField::INT32}, {"y", 4, PointField::FLOAT32},
                           {"z", 8, PointField::FLOAT32}},
                          12);
       },
       false, "INT32"},
      {"point_step too small", [] { return makeCloud(kXyz32, 10); }, false, "point_step"},
      {"float64 z past point_step",
       [] {
         return makeCloud({{"x", 0, PointField::FLOAT32}, {"y", 4, PointField::FLOAT32},
                           {"z", 8, PointField::FLOAT64}},
                          12);
       },
       false, "point_step"},
      {"data too short",
       [] {
         auto c = makeCloud(kXyz32, 12);
         c.data.pop_back();
         return c;
       },
       false, "needed"},
      {"organised data too short for row_step",
       [] {
         auto c = makeCloud(kXyz32, 12, 2, 2, 8);
         c.data.resize(c.row_step + 2 * 12 - 1);
         return c;
       },
       false, "needed"},
      {"row_step smaller than a row",
       [] {
         auto c = makeCloud(kXyz32, 12, 2, 2);
         c.row_step = 20;
         return c;
       },
       false, "row_step"},
      {"big endian",
       [] {
         auto c = makeCloud(kXyz32, 12);
         c.is_bigendian = true;
         return c;
       },
       false, "big-endian"},
  };

  for (const CloudCase& tc : cases) {
    SCOPED_TRACE(tc.name);
    const sensor_msgs::PointCloud2 cloud = tc.make();
    vt::MatrixX3d V(1, 3);
    V << 7, 7, 7;
    std::string error;
    const bool ok = rc::pointCloudToVertices(cloud, V, error);
    ASSERT_EQ(ok, tc.ok) << error;
    if (!ok) {
      EXPECT_NE(error.find(tc.errorContains), std::string::npos) << error;
      EXPECT_EQ(V.rows(), 1) << "V must be left unchanged on failure";
      continue;
    }
    ASSERT_EQ(V.rows(), static_cast<Eigen::Index>(cloud.width * cloud.height));
    for (Eigen::Index i = 0; i < V.rows(); ++i)
      for (int k = 0; k < 3; ++k)
        EXPECT_EQ(V(i, k), expected(static_cast<int>(i), k, tc.isDouble[k])) << "point " << i << " " << k;
  }
}

TEST(PointCloudToVertices, EmptyCloudGivesNoVertices) {
  sensor_msgs::PointCloud2 c;
  vt::MatrixX3d V;
  std::string error;
  ASSERT_TRUE(rc::pointCloudToVertices(c, V, error)) << error;
  EXPECT_EQ(V.rows(), 0);
}

namespace {

pcl_msgs::PolygonMesh meshMsg(std::vector<std::vector<std::uint32_t>> polygons) {
  pcl_msgs::PolygonMesh m;
  m.cloud = makeCloud(kXyz32, 12);
  for (auto& p : polygons) {
    pcl_msgs::Vertices v;
    v.vertices = std::move(p);
    m.polygons.push_back(v);
  }
  return m;
}

vt::TriMesh tetrahedron() {
  vt::TriMesh m;
  m.V.resize(4, 3);
  m.V << 0.1, 0.2, 0.3, 1.0 / 3.0, -0.7, 0.123456789, -2.5e-7, 1.25, 0.5, 0.3, 0.4, 1.1;
  m.F.resize(4, 3);
  m.F << 0, 2, 1, 0, 1, 3, 0, 3, 2, 1, 2, 3;
  return m;
}

}  // namespace

TEST(FromMsg, QuadBecomesTwoTriangles) {
  vt::TriMesh mesh;
  std::string error;
  ASSERT_TRUE(rc::fromMsg(meshMsg({{0, 1, 2, 3}, {3, 2, 1}}), mesh, error)) << error;
  EXPECT_EQ(mesh.V.rows(), kNumPoints);
  ASSERT_EQ(mesh.F.rows(), 3);
  EXPECT_EQ(mesh.F.row(0), Eigen::RowVector3i(0, 1, 2));
  EXPECT_EQ(mesh.F.row(1), Eigen::RowVector3i(0, 2, 3));
  EXPECT_EQ(mesh.F.row(2), Eigen::RowVector3i(3, 2, 1));
}

TEST(FromMsg, TwoVertexPolygonFails) {
  vt::TriMesh mesh = tetrahedron();
  std::string error;
  EXPECT_FALSE(rc::fromMsg(meshMsg({{0, 1, 2}, {0, 1}}), mesh, error));
  EXPECT_NE(error.find("polygon 1"), std::string::npos) << error;
  EXPECT_NE(error.find("2 vertices"), std::string::npos) << error;
  EXPECT_EQ(mesh.F.rows(), 4) << "mesh must be left unchanged on failure";
}

TEST(FromMsg, IndexOutOfRangeFails) {
  vt::TriMesh mesh;
  std::string error;
  EXPECT_FALSE(rc::fromMsg(meshMsg({{0, 1, 2}, {1, 2, kNumPoints}}), mesh, error));
  EXPECT_NE(error.find("polygon 1"), std::string::npos) << error;
  EXPECT_NE(error.find("vertex 4"), std::string::npos) << error;
}

TEST(FromMsg, BadCloudFails) {
  auto msg = meshMsg({{0, 1, 2}});
  msg.cloud.fields.pop_back();  // no z
  vt::TriMesh mesh;
  std::string error;
  EXPECT_FALSE(rc::fromMsg(msg, mesh, error));
  EXPECT_NE(error.find("'z'"), std::string::npos) << error;
}

TEST(FromMsg, NoPolygonsGivesNoFaces) {
  vt::TriMesh mesh;
  std::string error;
  ASSERT_TRUE(rc::fromMsg(meshMsg({}), mesh, error)) << error;
  EXPECT_EQ(mesh.V.rows(), kNumPoints);
  EXPECT_EQ(mesh.F.rows(), 0);
}

TEST(ToMsg, LayoutAndRoundTrip) {
  const vt::TriMesh mesh = tetrahedron();
  std_msgs::Header header;
  header.frame_id = "body";
  header.seq = 17;
  header.stamp.sec = 1234;
  pcl_msgs::PolygonMesh msg;
  rc::toMsg(mesh, header, msg);

  EXPECT_EQ(msg.header.frame_id, "body");
  EXPECT_EQ(msg.cloud.header.frame_id, "body");
  EXPECT_EQ(msg.cloud.header.stamp.sec, 1234u);
  EXPECT_EQ(msg.cloud.height, 1u);
  EXPECT_EQ(msg.cloud.width, 4u);
  EXPECT_EQ(msg.cloud.point_step, 12u);
  EXPECT_EQ(msg.cloud.row_step, 48u);
  EXPECT_EQ(msg.cloud.data.size(), 48u);
  EXPECT_TRUE(msg.cloud.is_dense);
  EXPECT_FALSE(msg.cloud.is_bigendian);
  ASSERT_EQ(msg.cloud.fields.size(), 3u);
  const char* names[3] = {"x", "y", "z"};
  for (int k = 0; k < 3; ++k) {
    EXPECT_EQ(msg.cloud.fields[k].name, names[k]);
    EXPECT_EQ(msg.cloud.fields[k].offset, 4u * k);
    EXPECT_EQ(msg.cloud.fields[k].datatype, PointField::FLOAT32);
    EXPECT_EQ(msg.cloud.fields[k].count, 1u);
  }
  ASSERT_EQ(msg.polygons.size(), 4u);

  vt::TriMesh back;
  std::string error;
  ASSERT_TRUE(rc::fromMsg(msg, back, error)) << error;
  ASSERT_EQ(back.V.rows(), mesh.V.rows());
  ASSERT_EQ(back.F.rows(), mesh.F.rows());
  EXPECT_TRUE((back.F.array() == mesh.F.array()).all());
  for (Eigen::Index i = 0; i < mesh.V.rows(); ++i)
    for (int k = 0; k < 3; ++k) {
      EXPECT_EQ(back.V(i, k), static_cast<double>(static_cast<float>(mesh.V(i, k))));
      EXPECT_NEAR(back.V(i, k), mesh.V(i, k), 1e-7 * std::max(1.0, std::abs(mesh.V(i, k))));
    }
}

TEST(ToTriangleListMarker, OnePointPerCorner) {
  const vt::TriMesh mesh = tetrahedron();
  std_msgs::ColorRGBA color;
  color.r = 0.2f;
  color.g = 0.4f;
  color.b = 0.6f;
  color.a = 0.8f;
  const visualization_msgs::Marker m = rc::toTriangleListMarker(mesh, "world", "garment", 3, color);
  EXPECT_EQ(m.header.frame_id, "world");
  EXPECT_EQ(m.ns, "garment");
  EXPECT_EQ(m.id, 3);
  EXPECT_EQ(m.type, visualization_msgs::Marker::TRIANGLE_LIST);
  EXPECT_EQ(m.action, visualization_msgs::Marker::ADD);
  EXPECT_EQ(m.pose.orientation.w, 1.0);
  EXPECT_EQ(m.pose.orientation.x, 0.0);
  EXPECT_EQ(m.pose.position.x, 0.0);
  EXPECT_EQ(m.scale.x, 1.0);
  EXPECT_EQ(m.scale.y, 1.0);
  EXPECT_EQ(m.scale.z, 1.0);
  EXPECT_EQ(m.color.r, 0.2f);
  EXPECT_EQ(m.color.a, 0.8f);
  ASSERT_EQ(m.points.size(), 3u * static_cast<std::size_t>(mesh.F.rows()));
  for (Eigen::Index f = 0; f < mesh.F.rows(); ++f)
    for (int k = 0; k < 3; ++k) {
      const auto& p = m.points[3 * f + k];
      const auto v = mesh.V.row(mesh.F(f, k));
      EXPECT_EQ(p.x, v(0));
      EXPECT_EQ(p.y, v(1));
      EXPECT_EQ(p.z, v(2));
    }
}
