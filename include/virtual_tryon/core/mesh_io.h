// Reading and writing triangle meshes through PCL: OBJ, PLY and STL, chosen by the file's
// extension (case-insensitive). Polygons with more than 3 sides are fan-triangulated;
// polygons with fewer are dropped and counted.
#pragma once

#include "virtual_tryon/core/mesh.h"

#include <string>

namespace virtual_tryon {

struct MeshReadInfo {
  std::size_t polygons_read = 0;
  std::size_t polygons_triangulated = 0;  // n-gons (n > 3) split into n - 2 triangles
  std::size_t polygons_dropped = 0;       // fewer than 3 vertices
};

// Reads `path` into `mesh`. Returns false and sets `error` (naming the file and the problem) when
// the file is missing, unreadable, of an unknown extension, or holds no usable triangle.
bool readMesh(const std::string& path, TriMesh& mesh, std::string& error,
              MeshReadInfo* info = nullptr);

// Writes `mesh` to `path` (format by extension) keeping vertex order. Returns false and sets
// `error` on failure.
bool writeMesh(const std::string& path, const TriMesh& mesh, std::string& error);

}  // namespace virtual_tryon
