// Conversions between ROS messages and the core's TriMesh. Plain functions, no state
// (grid_map style): the only place where pcl_msgs and visualization_msgs meet the core.
#pragma once

#include "virtual_tryon/core/mesh.h"

#include <pcl_msgs/PolygonMesh.h>
#include <sensor_msgs/PointCloud2.h>
#include <std_msgs/ColorRGBA.h>
#include <visualization_msgs/Marker.h>

#include <string>

namespace virtual_tryon {
namespace ros_conversions {

// Reads x, y, z from a PointCloud2 by field name and offset (FLOAT32 or FLOAT64, any point type
// that has them, any point_step), straight from the byte buffer. Returns false with `error`
// naming the problem (missing field, unsupported datatype, point_step or data too short,
// big-endian data). For height > 1 rows are row_step bytes apart. A cloud with no points gives a
// 0 x 3 V. On failure V is left unchanged.
bool pointCloudToVertices(const sensor_msgs::PointCloud2& cloud, MatrixX3d& V, std::string& error);

// PolygonMesh -> TriMesh. Polygons with more than 3 vertices are fan-triangulated; polygons with
// fewer than 3 vertices make the conversion fail (a mesh is not a point cloud). Indices are
// checked against the cloud size. A mesh with no polygons converts to a TriMesh with no faces.
// On failure `mesh` is left unchanged.
bool fromMsg(const pcl_msgs::PolygonMesh& msg, TriMesh& mesh, std::string& error);

// TriMesh -> PolygonMesh with FLOAT32 x, y, z fields (point_step 12, height 1, is_dense), same
// vertex order. The header is copied into msg.header and msg.cloud.header. Faces with an index
// outside [0, #V) are skipped (validate() the mesh first).
void toMsg(const TriMesh& mesh, const std_msgs::Header& header, pcl_msgs::PolygonMesh& msg);

// TriMesh -> TRIANGLE_LIST marker (one point per face corner, so 3 * #F points) in `frame_id`,
// identity pose, scale 1, uniform `color`, stamp 0 (latest transform). Faces with an index
// outside [0, #V) are skipped.
visualization_msgs::Marker toTriangleListMarker(const TriMesh& mesh, const std::string& frame_id,
                                                const std::string& ns, int id,
                                                const std_msgs::ColorRGBA& color);

}  // namespace ros_conversions
}  // namespace virtual_tryon
