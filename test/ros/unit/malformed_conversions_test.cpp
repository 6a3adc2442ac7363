// Malformed input to the mesh conversions, table-driven: each message goes through what the node
// does with it (ros_conversions::fromMsg, then validateBody for a body or validate for a
// garment, then placementWarnings), and each case names the exact outcome and a substring of
// the message. Also pointCloudToPoints (normals) and toMsg's FLOAT64 fallback.
#include "../../malformed_meshes.h"
#include "virtual_tryon/core/body/body_preparation.h"
#include "virtual_tryon/core/geometry/mesh.h"
#include "../cloud_builder.h"
#include "virtual_tryon/ros/conversions.h"

#include <gtest/gtest.h>

#include <sensor_msgs/PointField.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <functional>
#include <limits>
#include <optional>
#include <string>
#include <vector>

namespace vt = virtual_tryon;
namespace rc = virtual_tryon::ros_conversions;
using sensor_msgs::PointField;

namespace {

using Field = virtual_tryon_test::CloudField;

// A cloud holding the rows of V (x, y, z) and optionally N (normal_x, ...) laid out by `fields`.
sensor_msgs::PointCloud2 cloudOf(const vt::MatrixX3d& V, const std::vector<Field>& fields, std::uint32_t step,
                                 const vt::MatrixX3d* N = nullptr) {
  sensor_msgs::PointCloud2 c = virtual_tryon_test::buildCloud(
      fields, step, static_cast<std::uint32_t>(V.rows()), 1, 0, 0xCD, [&](int i, const Field& f) -> std::optional<double> {
        const bool normal = f.name.rfind("normal_", 0) == 0;
        const int k = f.name.back() - 'x';
        if (k < 0 || k > 2 || (f.name.size() > 1 && !normal) || (normal && !N)) return std::nullopt;
        return normal ? (*N)(i, k) : V(i, k);
      });
  c.is_dense = false;
  return c;
}

const std::vector<Field> kXyz64 = {{"x", 0, PointField::FLOAT64}, {"y", 8, PointField::FLOAT64}, {"z", 16, PointField::FLOAT64}};

// Exact FLOAT64 message of a mesh (the float32 of toMsg would round far-away coordinates).
pcl_msgs::PolygonMesh msg64(const vt::TriMesh& m) {
  pcl_msgs::PolygonMesh msg;
  msg.cloud = cloudOf(m.V, kXyz64, 24);
  for (Eigen::Index f = 0; f < m.F.rows(); ++f) {
    pcl_msgs::Vertices v;
    for (int k = 0; k < 3; ++k) v.vertices.push_back(static_cast<std::uint32_t>(m.F(f, k)));
    msg.polygons.push_back(v);
  }
  return msg;
}

vt::TriMesh square() {  // a unit square as four points, no faces
  vt::TriMesh m;
  m.V.resize(4, 3);
  m.V << 0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0;
  return m;
}

pcl_msgs::PolygonMesh withPolygons(pcl_msgs::PolygonMesh msg, const std::vector<std::vector<std::uint32_t>>& polys) {
  msg.polygons.clear();
  for (const auto& p : polys) {
    pcl_msgs::Vertices v;
    v.vertices = p;
    msg.polygons.push_back(v);
  }
  return msg;
}

enum class Outcome { ConvertFails, ValidateFails, Warns, Clean };

struct ConvCase {
  std::string name;
  std::function<pcl_msgs::PolygonMesh()> make;
  Outcome outcome;
  std::string message;  // substring of the error or of a warning
  bool body = false;    // checked as a body (validateBody) instead of a garment
  vt::MeshLimits limits = vt::MeshLimits();
  Eigen::Index triangles = -1;  // when converted: expected triangle count (-1: not checked)
};

// What the node does with one mesh message; returns the outcome and the message.
Outcome convert(const pcl_msgs::PolygonMesh& msg, bool body, const vt::MeshLimits& limits, vt::TriMesh& mesh,
                std::string& message) {
  if (!rc::fromMsg(msg, mesh, message, limits)) return Outcome::ConvertFails;
  const vt::MeshValidation v = body ? vt::validateBody(mesh, limits) : vt::validate(mesh, "garment", limits);
  message = v.message;
  if (!v.ok) return Outcome::ValidateFails;
  return v.warnings.empty() ? Outcome::Clean : Outcome::Warns;
}

const char* name(Outcome o) {
  switch (o) {
    case Outcome::ConvertFails: return "conversion fails";
    case Outcome::ValidateFails: return "validation fails";
    case Outcome::Warns: return "ok with a warning";
    case Outcome::Clean: return "ok";
  }
  return "?";
}

}  // namespace

TEST(MalformedConversions, MessageTable) {
  const vt::ResolveScene s = vt_malformed::goodScene();
  const pcl_msgs::PolygonMesh good = msg64(s.garment);
  vt::MeshLimits small;
  small.max_vertices = 3;
  vt::MeshLimits fewFaces;
  fewFaces.max_faces = 10;

  const std::vector<ConvCase> cases = {
      {"empty cloud with polygons", [&] { auto m = good; m.cloud = sensor_msgs::PointCloud2(); return m; },
       Outcome::ConvertFails, "refers to vertex"},
      {"empty cloud, no polygons", [] { return pcl_msgs::PolygonMesh(); }, Outcome::ValidateFails, "has no vertices"},
      {"empty polygon list", [&] { return withPolygons(good, {}); }, Outcome::ValidateFails, "garment has no faces"},
      {"cloud without x, y, z fields",
       [&] {
         auto m = good;
         for (auto& f : m.cloud.fields) f.name = "intensity_" + f.name;
         return m;
       },
       Outcome::ConvertFails, "no 'x' field"},
      {"x, y, z as FLOAT64", [&] { return good; }, Outcome::Clean, "", false, vt::MeshLimits(), s.garment.F.rows()},
      {"odd offsets, mixed FLOAT32 / FLOAT64",
       [&] {
         auto m = good;
         m.cloud = cloudOf(s.garment.V, {{"y", 1, PointField::FLOAT64}, {"x", 9, PointField::FLOAT32},
                                         {"z", 13, PointField::FLOAT64}, {"rgb", 21, PointField::FLOAT32}},
                           27);
         return m;
       },
       Outcome::Clean, ""},
      {"point_step smaller than the fields",
       [&] {
         auto m = good;
         m.cloud.point_step = 20;
         m.cloud.row_step = 20 * m.cloud.width;
         return m;
       },
       Outcome::ConvertFails, "point_step 20 is too small for field 'z'"},
      {"data shorter than width * height * point_step",
       [&] {
         auto m = good;
         m.cloud.data.resize(m.cloud.data.size() - 1);
         return m;
       },
       Outcome::ConvertFails, "needed for"},
      {"organised cloud with row_step smaller than a row",
       [&] {
         auto m = withPolygons(good, {{0, 1, 2}});
         m.cloud.width = 2;
         m.cloud.height = 2;
         m.cloud.row_step = 40;
         return m;
       },
       Outcome::ConvertFails, "row_step 40 is smaller"},
      {"big-endian", [&] { auto m = good; m.cloud.is_bigendian = true; return m; }, Outcome::ConvertFails, "big-endian"},
      {"integer coordinates",
       [&] { auto m = good; m.cloud.fields[1].datatype = PointField::INT32; return m; }, Outcome::ConvertFails,
       "only FLOAT32 and FLOAT64"},
      {"polygon index out of range",
       [&] { auto m = good; m.polygons[7].vertices[2] = 100000; return m; }, Outcome::ConvertFails,
       "polygon 7 refers to vertex 100000"},
      {"negative polygon index",
       [&] { auto m = good; m.polygons[3].vertices[0] = static_cast<std::uint32_t>(-1); return m; },
       Outcome::ConvertFails, "(-1 as a signed index)"},
      {"polygon of 1 vertex", [&] { auto m = good; m.polygons[2].vertices = {4}; return m; }, Outcome::ConvertFails,
       "polygon 2 has 1 vertices; at least 3"},
      {"polygon of 2 vertices", [&] { auto m = good; m.polygons[0].vertices = {4, 5}; return m; },
       Outcome::ConvertFails, "polygon 0 has 2 vertices; at least 3"},
      {"n-gons are fan-triangulated", [] { return withPolygons(msg64(square()), {{0, 1, 2, 3}, {0, 1, 2, 3, 0}}); },
       Outcome::Warns, "duplicate face", false, vt::MeshLimits(), 5},
      {"a quad", [] { return withPolygons(msg64(square()), {{0, 1, 2, 3}}); }, Outcome::Clean, "", false,
       vt::MeshLimits(), 2},
      {"3 million points (over the default limit), no data",
       [] {
         pcl_msgs::PolygonMesh m = withPolygons(msg64(square()), {{0, 1, 2}});
         m.cloud.width = 3000000;
         m.cloud.row_step = m.cloud.width * m.cloud.point_step;
         m.cloud.data.clear();  // refused on width * height before the data is looked at
         return m;
       },
       Outcome::ConvertFails, "3000000 points, over the limit of 2000000 vertices"},
      {"2^32 - 1 squared points",
       [] {
         pcl_msgs::PolygonMesh m = msg64(square());
         m.cloud.width = m.cloud.height = 0xFFFFFFFFu;
         return m;
       },
       Outcome::ConvertFails, "over the limit"},
      {"more points than a set limit", [] { return withPolygons(msg64(square()), {{0, 1, 2}}); },
       Outcome::ConvertFails, "over the limit of 3 vertices", false, small},
      {"more triangles than a set limit", [&] { return good; }, Outcome::ConvertFails,
       "over the limit of 10 triangles", false, fewFaces},
  };

  for (const ConvCase& tc : cases) {
    SCOPED_TRACE(tc.name);
    vt::TriMesh mesh;
    std::string message;
    const Outcome got = convert(tc.make(), tc.body, tc.limits, mesh, message);
    EXPECT_EQ(name(got), std::string(name(tc.outcome))) << message;
    EXPECT_NE(message.find(tc.message), std::string::npos) << "'" << tc.message << "' not in: " << message;
    if (tc.triangles >= 0) {
      EXPECT_EQ(mesh.F.rows(), tc.triangles);
    }
  }
  // And a good message still converts.
  vt::TriMesh mesh;
  std::string message;
  ASSERT_EQ(name(convert(good, false, vt::MeshLimits(), mesh, message)), std::string(name(Outcome::Clean))) << message;
  EXPECT_TRUE(mesh.V == s.garment.V);
  EXPECT_TRUE(mesh.F == s.garment.F);
}

TEST(MalformedConversions, SharedMeshCases) {
  for (const vt_malformed::MeshCase& tc : vt_malformed::meshCases()) {
    SCOPED_TRACE(tc.name);
    vt::TriMesh body, garment;
    std::string bodyMessage, garmentMessage;
    const Outcome b = convert(msg64(tc.body), true, vt::MeshLimits(), body, bodyMessage);
    const Outcome g = convert(msg64(tc.garment), false, vt::MeshLimits(), garment, garmentMessage);
    std::vector<std::string> messages = {bodyMessage, garmentMessage};
    const bool ok = (b == Outcome::Clean || b == Outcome::Warns) && (g == Outcome::Clean || g == Outcome::Warns);
    EXPECT_EQ(ok, tc.ok) << bodyMessage << " | " << garmentMessage;
    if (ok)
      for (const std::string& w : vt::placementWarnings(body, garment)) messages.push_back(w);
    bool found = false;
    for (const std::string& m : messages) found = found || m.find(tc.message) != std::string::npos;
    EXPECT_TRUE(found) << "'" << tc.message << "' in none of: " << bodyMessage << " | " << garmentMessage;
    if (tc.ok && !tc.warns) {
      EXPECT_TRUE(bodyMessage.empty() && garmentMessage.empty());
    }
  }
}

TEST(PointCloudToPoints, ReadsNormalsByNameAnyTypeAndOffset) {
  const vt::TriMesh sq = square();
  vt::MatrixX3d N(4, 3);
  N << 0, 0, 1, 0, 0.6, 0.8, 1, 0, 0, -0.36, 0.48, 0.8;
  // normal_z as FLOAT64 at an odd offset, the rest FLOAT32, fields out of order.
  const sensor_msgs::PointCloud2 c =
      cloudOf(sq.V, {{"normal_z", 13, PointField::FLOAT64}, {"x", 0, PointField::FLOAT32},
                     {"normal_x", 21, PointField::FLOAT32}, {"y", 4, PointField::FLOAT32},
                     {"z", 8, PointField::FLOAT32}, {"normal_y", 25, PointField::FLOAT32}},
              29, &N);
  vt::MatrixX3d V, got;
  std::string error;
  ASSERT_TRUE(rc::pointCloudToPoints(c, V, &got, error)) << error;
  ASSERT_EQ(got.rows(), 4);
  for (int i = 0; i < 4; ++i) {
    EXPECT_EQ(got(i, 2), N(i, 2));  // FLOAT64: exact
    EXPECT_EQ(got(i, 0), static_cast<double>(static_cast<float>(N(i, 0))));
    EXPECT_EQ(got(i, 1), static_cast<double>(static_cast<float>(N(i, 1))));
    EXPECT_EQ(V.row(i), sq.V.row(i));
  }
  // Without the normals argument, the same points.
  vt::MatrixX3d V2;
  ASSERT_TRUE(rc::pointCloudToVertices(c, V2, error)) << error;
  EXPECT_TRUE(V2 == V);
}

TEST(PointCloudToPoints, NoNormalFieldsGiveNoNormals) {
  vt::MatrixX3d V, N(1, 3);
  std::string error;
  ASSERT_TRUE(rc::pointCloudToPoints(cloudOf(square().V, kXyz64, 24), V, &N, error)) << error;
  EXPECT_EQ(V.rows(), 4);
  EXPECT_EQ(N.rows(), 0);
}

TEST(PointCloudToPoints, SomeNormalFieldsOnlyFail) {
  const sensor_msgs::PointCloud2 c = cloudOf(square().V, {{"x", 0, PointField::FLOAT32}, {"y", 4, PointField::FLOAT32},
                                                          {"z", 8, PointField::FLOAT32}, {"normal_x", 12, PointField::FLOAT32},
                                                          {"normal_z", 16, PointField::FLOAT32}},
                                             20);
  vt::MatrixX3d V(1, 3), N(1, 3);
  std::string error;
  EXPECT_FALSE(rc::pointCloudToPoints(c, V, &N, error));
  EXPECT_NE(error.find("'normal_y'"), std::string::npos) << error;
  EXPECT_EQ(V.rows(), 1) << "left unchanged";
  // Points alone still read.
  EXPECT_TRUE(rc::pointCloudToVertices(c, V, error)) << error;
  // A normal field outside point_step fails like a coordinate would.
  sensor_msgs::PointCloud2 d = cloudOf(square().V, {{"x", 0, PointField::FLOAT32}, {"y", 4, PointField::FLOAT32},
                                                    {"z", 8, PointField::FLOAT32}, {"normal_x", 12, PointField::FLOAT32},
                                                    {"normal_y", 16, PointField::FLOAT32}, {"normal_z", 20, PointField::FLOAT64}},
                                       24);
  EXPECT_FALSE(rc::pointCloudToPoints(d, V, &N, error));
  EXPECT_NE(error.find("point_step 24 is too small for field 'normal_z'"), std::string::npos) << error;
}

TEST(ToMsg, FarCoordinatesAreSentAsFloat64) {
  vt::TriMesh m = vt_malformed::goodScene().garment;
  m.V.col(0).array() += 1e6;  // 1000 km: float32 would round to 6 cm
  pcl_msgs::PolygonMesh msg;
  rc::toMsg(m, std_msgs::Header(), msg);
  ASSERT_EQ(msg.cloud.fields.size(), 3u);
  EXPECT_EQ(msg.cloud.fields[0].datatype, PointField::FLOAT64);
  EXPECT_EQ(msg.cloud.point_step, 24u);
  vt::TriMesh back;
  std::string error;
  ASSERT_TRUE(rc::fromMsg(msg, back, error)) << error;
  EXPECT_TRUE(back.V == m.V) << "exact";
  // A metre-scale mesh stays FLOAT32.
  rc::toMsg(vt_malformed::goodScene().garment, std_msgs::Header(), msg);
  EXPECT_EQ(msg.cloud.fields[0].datatype, PointField::FLOAT32);
  EXPECT_EQ(msg.cloud.point_step, 12u);
}
