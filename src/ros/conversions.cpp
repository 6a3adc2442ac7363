#include "virtual_tryon/ros/conversions.h"

#include "virtual_tryon/core/io/point_records.h"

#include <sensor_msgs/PointField.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <utility>

namespace virtual_tryon {
namespace ros_conversions {
namespace {

using PF = sensor_msgs::PointField;
static_assert(PF::INT8 == kPointInt8 && PF::UINT8 == kPointUInt8 && PF::INT16 == kPointInt16 &&
                  PF::UINT16 == kPointUInt16 && PF::INT32 == kPointInt32 && PF::UINT32 == kPointUInt32 &&
                  PF::FLOAT32 == kPointFloat32 && PF::FLOAT64 == kPointFloat64,
              "sensor_msgs::PointField datatypes differ from point_records.h");

bool faceIsValid(const TriMesh& mesh, Eigen::Index f) {
  const Eigen::Index n = mesh.V.rows();
  for (int k = 0; k < 3; ++k)
    if (mesh.F(f, k) < 0 || mesh.F(f, k) >= n) return false;
  return true;
}

// The fields pointCloudToPoints reads: x, y, z, then normal_x, normal_y, normal_z when wanted and
// present.
const char* const kCloudFields[6] = {"x", "y", "z", "normal_x", "normal_y", "normal_z"};

// The point count (width * height > 0) against the limits and what a mesh can index.
bool checkCloudSize(const PointRecords& cloud, const MeshLimits& limits, std::string& error) {
  const std::uint64_t n = cloud.points();
  if (n > limits.max_vertices) {
    error = "point cloud has " + std::to_string(cloud.width) + " x " + std::to_string(cloud.height) + " = " +
            std::to_string(n) + " points, over the limit of " + std::to_string(limits.max_vertices) +
            " vertices (MeshLimits::max_vertices)";
    return false;
  }
  if (n > static_cast<std::uint64_t>(std::numeric_limits<int>::max())) {
    error = "point cloud has " + std::to_string(n) + " points, more than a mesh can index";
    return false;
  }
  return true;
}

// Field `name` of the cloud: FLOAT32 or FLOAT64, inside point_step.
bool checkCloudField(const PointRecordField& f, const char* name, std::uint32_t step, std::string& error) {
  switch (checkFloatField(f, step)) {
    case FloatFieldProblem::NotFloat:
      error = std::string("point cloud field '") + name + "' has datatype " + pointDatatypeName(f.datatype) +
              " (" + std::to_string(f.datatype) + "); only FLOAT32 and FLOAT64 are supported";
      return false;
    case FloatFieldProblem::OutsidePointStep:
      error = "point_step " + std::to_string(step) + " is too small for field '" + name + "' (offset " +
              std::to_string(f.offset) + ", " + std::to_string(floatFieldBytes(f)) + " bytes)";
      return false;
    case FloatFieldProblem::None: break;
  }
  return true;
}

// Finds the fields to read, kCloudFields[0 .. fieldCount): x, y, z (required), then the three
// normal fields when `wantNormals` and the cloud has any of them (then it must have all three),
// and checks each.
bool findCloudFields(const PointRecords& cloud, bool wantNormals, const PointRecordField* (&found)[6],
                     int& fieldCount, std::string& error) {
  for (int k = 0; k < 6; ++k) found[k] = cloud.field(kCloudFields[k]);
  for (int k = 0; k < 3; ++k)
    if (!found[k]) {
      error = std::string("point cloud has no '") + kCloudFields[k] + "' field";
      return false;
    }
  fieldCount = 3;
  if (wantNormals && (found[3] || found[4] || found[5])) {
    for (int k = 3; k < 6; ++k)
      if (!found[k]) {
        error = std::string("point cloud has some normal fields but no '") + kCloudFields[k] +
                "' (normal_x, normal_y and normal_z go together)";
        return false;
      }
    fieldCount = 6;
  }
  for (int k = 0; k < fieldCount; ++k)
    if (!checkCloudField(*found[k], kCloudFields[k], cloud.point_step, error)) return false;
  return true;
}

// The data holds every point: row_step (height > 1) and the buffer size.
bool checkCloudExtent(const PointRecords& cloud, std::string& error) {
  switch (checkPointExtent(cloud)) {
    case PointExtentProblem::RowStepTooSmall:
      error = "row_step " + std::to_string(cloud.rowStride()) + " is smaller than width * point_step = " +
              std::to_string(cloud.rowBytes());
      return false;
    case PointExtentProblem::DataTooShort:
      error = "point cloud data has " + std::to_string(cloud.size) + " bytes, " +
              std::to_string(cloud.bytesNeeded()) + " needed for " + std::to_string(cloud.width) + " x " +
              std::to_string(cloud.height) + " points of " + std::to_string(cloud.point_step) + " bytes";
      return false;
    case PointExtentProblem::None: break;
  }
  return true;
}

}  // namespace

bool pointCloudToPoints(const sensor_msgs::PointCloud2& msg, MatrixX3d& V, MatrixX3d* normals,
                        std::string& error, const MeshLimits& limits) {
  const PointRecords cloud = viewPointRecords(msg);
  if (cloud.is_bigendian) {
    error = "point cloud is big-endian (is_bigendian = true); only little-endian data is supported";
    return false;
  }
  const std::uint64_t n = cloud.points();
  if (n == 0) {
    V.resize(0, 3);
    if (normals) normals->resize(0, 3);
    return true;
  }
  if (!checkCloudSize(cloud, limits, error)) return false;
  const PointRecordField* fields[6];
  int fieldCount = 3;
  if (!findCloudFields(cloud, normals != nullptr, fields, fieldCount, error)) return false;
  if (!checkCloudExtent(cloud, error)) return false;

  MatrixX3d out(static_cast<Eigen::Index>(n), 3);
  MatrixX3d outNormals(fieldCount == 6 ? static_cast<Eigen::Index>(n) : 0, 3);
  readFloatFields(cloud, fields, fieldCount, [&](std::uint64_t i, int k, double v) {
    if (k < 3)
      out(static_cast<Eigen::Index>(i), k) = v;
    else
      outNormals(static_cast<Eigen::Index>(i), k - 3) = v;
  });
  V = std::move(out);
  if (normals) *normals = std::move(outNormals);
  return true;
}

bool pointCloudToVertices(const sensor_msgs::PointCloud2& cloud, MatrixX3d& V, std::string& error,
                          const MeshLimits& limits) {
  return pointCloudToPoints(cloud, V, nullptr, error, limits);
}

bool fromMsg(const pcl_msgs::PolygonMesh& msg, TriMesh& mesh, std::string& error,
             const MeshLimits& limits) {
  // Sizes first: the points (pointCloudToPoints checks width * height before reading) and the
  // triangles the polygons make, before either is allocated.
  std::uint64_t triangles = 0;
  for (std::size_t p = 0; p < msg.polygons.size(); ++p) {
    const auto& verts = msg.polygons[p].vertices;
    if (verts.size() < 3) {
      error = "polygon " + std::to_string(p) + " has " + std::to_string(verts.size()) +
              " vertices; at least 3 are needed";
      return false;
    }
    triangles += verts.size() - 2;
  }
  if (triangles > limits.max_faces) {
    error = std::to_string(msg.polygons.size()) + " polygons make " + std::to_string(triangles) +
            " triangles, over the limit of " + std::to_string(limits.max_faces) +
            " triangles (MeshLimits::max_faces)";
    return false;
  }
  if (triangles > static_cast<std::uint64_t>(std::numeric_limits<int>::max())) {
    error = "too many triangles";
    return false;
  }

  TriMesh out;
  if (!pointCloudToVertices(msg.cloud, out.V, error, limits)) return false;
  const std::uint64_t n = static_cast<std::uint64_t>(out.V.rows());
  for (std::size_t p = 0; p < msg.polygons.size(); ++p)
    for (const std::uint32_t v : msg.polygons[p].vertices)
      if (v >= n) {
        error = "polygon " + std::to_string(p) + " refers to vertex " + std::to_string(v) +
                (v >= 0x80000000u ? " (" + std::to_string(static_cast<std::int32_t>(v)) +
                                        " as a signed index)"
                                  : std::string()) +
                " but the cloud has " + std::to_string(n) + " points";
        return false;
      }

  out.F.resize(static_cast<Eigen::Index>(triangles), 3);
  Eigen::Index f = 0;
  for (const auto& poly : msg.polygons) {
    const auto& v = poly.vertices;
    for (std::size_t k = 1; k + 1 < v.size(); ++k, ++f) {  // fan around the first corner
      out.F(f, 0) = static_cast<int>(v[0]);
      out.F(f, 1) = static_cast<int>(v[k]);
      out.F(f, 2) = static_cast<int>(v[k + 1]);
    }
  }
  mesh = std::move(out);
  return true;
}

void toMsg(const TriMesh& mesh, const std_msgs::Header& header, pcl_msgs::PolygonMesh& msg) {
  msg.header = header;
  sensor_msgs::PointCloud2& c = msg.cloud;
  c.header = header;
  c.height = 1;
  c.width = static_cast<std::uint32_t>(mesh.V.rows());
  bool wide = false;  // FLOAT64 when float32 would round a coordinate by more than a micrometre
  for (Eigen::Index i = 0; i < mesh.V.rows() && !wide; ++i)
    for (int k = 0; k < 3; ++k)
      if (std::abs(mesh.V(i, k)) > kFloat32ExactRange && std::isfinite(mesh.V(i, k))) wide = true;
  const std::uint32_t size = wide ? 8 : 4;
  c.fields.resize(3);
  const char* names[3] = {"x", "y", "z"};
  for (int k = 0; k < 3; ++k) {
    c.fields[k].name = names[k];
    c.fields[k].offset = static_cast<std::uint32_t>(size * k);
    c.fields[k].datatype = wide ? sensor_msgs::PointField::FLOAT64 : sensor_msgs::PointField::FLOAT32;
    c.fields[k].count = 1;
  }
  c.is_bigendian = false;
  c.point_step = 3 * size;
  c.row_step = c.point_step * c.width;
  c.is_dense = true;
  c.data.resize(static_cast<std::size_t>(c.row_step));
  std::uint8_t* out = c.data.data();
  for (Eigen::Index i = 0; i < mesh.V.rows(); ++i)
    for (int k = 0; k < 3; ++k, out += size) {
      if (wide) {
        const double v = mesh.V(i, k);
        std::memcpy(out, &v, sizeof v);
      } else {
        const float v = static_cast<float>(mesh.V(i, k));
        std::memcpy(out, &v, sizeof v);
      }
    }

  msg.polygons.clear();
  msg.polygons.reserve(static_cast<std::size_t>(mesh.F.rows()));
  for (Eigen::Index f = 0; f < mesh.F.rows(); ++f) {
    if (!faceIsValid(mesh, f)) continue;
    pcl_msgs::Vertices v;
    v.vertices = {static_cast<std::uint32_t>(mesh.F(f, 0)), static_cast<std::uint32_t>(mesh.F(f, 1)),
                  static_cast<std::uint32_t>(mesh.F(f, 2))};
    msg.polygons.push_back(std::move(v));
  }
}

visualization_msgs::Marker toTriangleListMarker(const TriMesh& mesh, const std::string& frame_id,
                                                const std::string& ns, int id,
                                                const std_msgs::ColorRGBA& color,
                                                const std::vector<std_msgs::ColorRGBA>* vertex_colors) {
  const bool perVertex = vertex_colors && vertex_colors->size() == static_cast<std::size_t>(mesh.V.rows());
  visualization_msgs::Marker m;
  m.header.frame_id = frame_id;
  m.ns = ns;
  m.id = id;
  m.type = visualization_msgs::Marker::TRIANGLE_LIST;
  m.action = visualization_msgs::Marker::ADD;
  m.pose.orientation.x = 0.0;
  m.pose.orientation.y = 0.0;
  m.pose.orientation.z = 0.0;
  m.pose.orientation.w = 1.0;
  m.scale.x = m.scale.y = m.scale.z = 1.0;
  m.color = color;
  m.points.reserve(static_cast<std::size_t>(mesh.F.rows()) * 3);
  if (perVertex) m.colors.reserve(m.points.capacity());
  for (Eigen::Index f = 0; f < mesh.F.rows(); ++f) {
    if (!faceIsValid(mesh, f)) continue;
    for (int k = 0; k < 3; ++k) {
      const auto row = mesh.V.row(mesh.F(f, k));
      geometry_msgs::Point p;
      p.x = row(0);
      p.y = row(1);
      p.z = row(2);
      m.points.push_back(p);
      if (perVertex) m.colors.push_back((*vertex_colors)[static_cast<std::size_t>(mesh.F(f, k))]);
    }
  }
  return m;
}

}  // namespace ros_conversions
}  // namespace virtual_tryon
