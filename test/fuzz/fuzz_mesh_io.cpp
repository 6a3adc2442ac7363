// libFuzzer target: the mesh file readers (mesh_io: own OBJ reader; PLY and STL through our
// header / size checks, then PCL / VTK). The first byte picks the format ('o' OBJ, 'p' PLY,
// 's' STL, anything else by its value mod 3); the rest is the file, written to a temporary file
// because the readers take paths.
#include "virtual_tryon/core/body/body_preparation.h"
#include "virtual_tryon/core/geometry/mesh.h"
#include "virtual_tryon/core/io/mesh_io.h"

#include <pcl/console/print.h>
#include <vtkObject.h>

#include <unistd.h>

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>

namespace vt = virtual_tryon;

namespace {
std::string tempBase;
}

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  pcl::console::setVerbosityLevel(pcl::console::L_ALWAYS);
  vtkObject::GlobalWarningDisplayOff();
  const char* dir = std::getenv("TMPDIR");
  tempBase = std::string(dir && *dir ? dir : "/tmp") + "/vt_fuzz_mesh_io_" + std::to_string(::getpid());
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size < 1) return 0;
  const char* ext = nullptr;
  switch (data[0]) {
    case 'o': ext = ".obj"; break;
    case 'p': ext = ".ply"; break;
    case 's': ext = ".stl"; break;
    default: ext = data[0] % 3 == 0 ? ".obj" : data[0] % 3 == 1 ? ".ply" : ".stl";
  }
  const std::string path = tempBase + ext;
  std::FILE* f = std::fopen(path.c_str(), "wb");
  if (!f) std::abort();
  if (size > 1 && std::fwrite(data + 1, 1, size - 1, f) != size - 1) std::abort();
  std::fclose(f);

  vt::TriMesh mesh;
  std::string error;
  vt::MeshReadInfo info;
  vt::MeshLimits limits;
  limits.max_vertices = 100000;  // keeps PCL's allocations small; the checks are the same
  limits.max_faces = 200000;
  const bool ok = vt::readMesh(path, mesh, error, &info, limits);
  std::remove(path.c_str());
  if (!ok) {
    if (error.empty()) std::abort();
    return 0;
  }
  if (mesh.V.rows() == 0 || mesh.F.rows() == 0) std::abort();  // readMesh promises a triangle
  const vt::MeshValidation v = vt::validateBody(mesh, limits);
  if (v.out_of_range_indices != 0) std::abort();  // the readers check every index
  return 0;
}
