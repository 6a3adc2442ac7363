// Reading and writing triangle meshes: OBJ, PLY and STL, chosen by the file's extension
// (case-insensitive). Polygons with more than 3 sides are fan-triangulated around their first
// corner; polygons with fewer are dropped and counted.
//
//  * OBJ: own reader and writer. Reads `v` and `f` lines (`f a`, `a/b`, `a//c`, `a/b/c`, negative
//    = relative indices), ignores everything else. Written in the shortest decimal form that
//    reads back to the same double, so OBJ round trips are exact.
//  * PLY: own reader (ASCII, binary little- or big-endian; vertex x, y, z of any scalar type,
//    other properties and elements skipped; faces from the `vertex_indices` / `vertex_index`
//    list); written as binary PLY with `double` x, y, z (exact round trip).
//  * STL: read and written through PCL/VTK (pcl::io::loadPolygonFileSTL / savePolygonFileSTL,
//    binary on write). STL stores float32 corners per triangle: reading welds exactly-equal
//    coordinates into one vertex, numbered in order of first appearance in the face list, and
//    VTK drops triangles made degenerate by the weld; unused vertices are not stored.
// Vertex order is kept as in the file (OBJ, PLY) or by first appearance (STL).
#pragma once

#include "virtual_tryon/core/geometry/mesh.h"

#include <string>

namespace virtual_tryon {

struct MeshReadInfo {
  std::size_t polygons_read = 0;
  std::size_t polygons_triangulated = 0;  // n-gons (n > 3) split into n - 2 triangles
  std::size_t polygons_dropped = 0;       // fewer than 3 vertices
};

// Reads `path` into `mesh`. Returns false and sets `error` (naming the file and the problem) when
// the file is missing, unreadable, of an unknown extension, holds no usable triangle, or is over
// `limits`. The limits are checked before anything of the declared size is allocated: OBJ while
// reading, PLY from its header (whose element counts must also fit in the file), binary STL from
// its triangle count (which must match the file size) before PCL/VTK read the file.
bool readMesh(const std::string& path, TriMesh& mesh, std::string& error,
              MeshReadInfo* info = nullptr, const MeshLimits& limits = MeshLimits());

// Writes `mesh` to `path` (format by extension) keeping vertex order. Returns false and sets
// `error` on failure.
bool writeMesh(const std::string& path, const TriMesh& mesh, std::string& error);

}  // namespace virtual_tryon
