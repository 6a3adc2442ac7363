// Conversions between ROS messages and the core's TriMesh. Plain functions, no state
// (grid_map style): the only place where pcl_msgs and visualization_msgs meet the core.
#pragma once

#include "virtual_tryon/core/geometry/mesh.h"

#include <pcl_msgs/PolygonMesh.h>
#include <sensor_msgs/PointCloud2.h>
#include <std_msgs/ColorRGBA.h>
#include <visualization_msgs/Marker.h>

#include <string>
#include <vector>

namespace virtual_tryon {
namespace ros_conversions {

// Reads points from a PointCloud2 by field name and offset, straight from the byte buffer: x, y, z
// (required) and, when `normals` is given and the cloud has them, normal_x, normal_y, normal_z.
// Each field may be FLOAT32 or FLOAT64 at any offset (unaligned is fine) in any point type; rows
// are row_step bytes apart when height > 1. Checked before anything is allocated: is_bigendian
// false; width * height within limits.max_vertices; every field read lies inside point_step; for
// height > 1, row_step >= width * point_step; data holds row_step * (height - 1) +
// width * point_step bytes. Returns false with `error` naming the problem (missing field,
// unsupported datatype, point_step, row_step or data too short, big-endian data, over the limit,
// only some of the normal fields). A cloud with no points gives 0 x 3 matrices. `normals`
// receives #V by 3 normals as stored (not normalized), or 0 x 3 when the cloud has no normal
// fields. Values are copied as they are (NaN included: validate() the mesh). On failure V and
// normals are left unchanged.
bool pointCloudToPoints(const sensor_msgs::PointCloud2& cloud, MatrixX3d& V, MatrixX3d* normals,
                        std::string& error, const MeshLimits& limits = MeshLimits());

// pointCloudToPoints without normals.
bool pointCloudToVertices(const sensor_msgs::PointCloud2& cloud, MatrixX3d& V, std::string& error,
                          const MeshLimits& limits = MeshLimits());

// PolygonMesh -> TriMesh. Polygons with more than 3 vertices are fan-triangulated; polygons with
// fewer than 3 vertices make the conversion fail (a mesh is not a point cloud). Indices are
// checked against the cloud size. The point count and the triangle count (summed from the polygon
// sizes) are checked against `limits` before anything of that size is allocated. A mesh with no
// polygons converts to a TriMesh with no faces. On failure `mesh` is left unchanged.
bool fromMsg(const pcl_msgs::PolygonMesh& msg, TriMesh& mesh, std::string& error,
             const MeshLimits& limits = MeshLimits());

// TriMesh -> PolygonMesh with FLOAT32 x, y, z fields (point_step 12, height 1, is_dense), same
// vertex order; FLOAT64 x, y, z (point_step 24) instead when a coordinate is larger in magnitude
// than kFloat32ExactRange metres, where float32 would move points by more than a micrometre (a
// scene in millimetres, or far from its frame's origin), so coordinates are never silently
// rounded to centimetres. Non-finite coordinates are kept as they are (FLOAT32). The header is copied into msg.header and msg.cloud.header. Faces with an index
// outside [0, #V) are skipped (validate() the mesh first).
void toMsg(const TriMesh& mesh, const std_msgs::Header& header, pcl_msgs::PolygonMesh& msg);

// Float32 spacing is below 1e-6 m for magnitudes under 8 m.
constexpr double kFloat32ExactRange = 8.0;

// TriMesh -> TRIANGLE_LIST marker (one point per face corner, so 3 * #F points) in `frame_id`,
// identity pose, scale 1, uniform `color`, stamp 0 (latest transform). Faces with an index
// outside [0, #V) are skipped.
// vertex_colors (#V, optional): a colour per mesh vertex, copied to every triangle corner (the
// marker's `colors`); else `color` for all.
visualization_msgs::Marker toTriangleListMarker(const TriMesh& mesh, const std::string& frame_id,
                                                const std::string& ns, int id,
                                                const std_msgs::ColorRGBA& color,
                                                const std::vector<std_msgs::ColorRGBA>* vertex_colors = nullptr);

}  // namespace ros_conversions
}  // namespace virtual_tryon
