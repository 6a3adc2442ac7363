#include "virtual_tryon/core/io/mesh_io.h"

#include <gtest/gtest.h>

#include <unistd.h>

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <string>

namespace vt = virtual_tryon;

namespace {

// A fresh directory under ::testing::TempDir(), removed with its files at the end of the test.
class MeshIoTest : public ::testing::Test {
 protected:
  void SetUp() override {
    std::string tmpl = ::testing::TempDir();
    if (tmpl.empty() || tmpl.back() != '/') tmpl += '/';
    tmpl += "mesh_io_XXXXXX";
    ASSERT_NE(mkdtemp(&tmpl[0]), nullptr);
    dir_ = tmpl;
  }
  void TearDown() override {
    for (const auto& f : files_) std::remove(f.c_str());
    if (!dir_.empty()) rmdir(dir_.c_str());
  }
  std::string path(const std::string& name) {
    files_.push_back(dir_ + "/" + name);
    return files_.back();
  }
  std::string writeText(const std::string& name, const std::string& text) {
    const std::string p = path(name);
    std::ofstream(p, std::ios::binary) << text;
    return p;
  }

  std::string dir_;
  std::vector<std::string> files_;
};

// Closed, outward-oriented tetrahedron with coordinates that are not exact in float32.
vt::TriMesh tetrahedron() {
  vt::TriMesh m;
  m.V.resize(4, 3);
  m.V << 0.1, 0.2, 0.30000000000000004,  //
      1.0 / 3.0, -0.7, 0.123456789012345,  //
      -2.5e-7, 1.25, 0.5,                  //
      0.3, 0.4, 1.1;
  m.F.resize(4, 3);
  m.F << 0, 2, 1,  //
      0, 1, 3,     //
      0, 3, 2,     //
      1, 2, 3;
  return m;
}

void expectSameTopology(const vt::TriMesh& a, const vt::TriMesh& b) {
  ASSERT_EQ(a.V.rows(), b.V.rows());
  ASSERT_EQ(a.F.rows(), b.F.rows());
  EXPECT_TRUE((a.F.array() == b.F.array()).all()) << "a.F=\n" << a.F << "\nb.F=\n" << b.F;
}

}  // namespace

TEST_F(MeshIoTest, ObjRoundTripIsExact) {
  const vt::TriMesh m = tetrahedron();
  std::string error;
  const std::string p = path("tet.obj");
  ASSERT_TRUE(vt::writeMesh(p, m, error)) << error;
  vt::TriMesh r;
  vt::MeshReadInfo info;
  ASSERT_TRUE(vt::readMesh(p, r, error, &info)) << error;
  EXPECT_TRUE(error.empty());
  expectSameTopology(m, r);
  EXPECT_TRUE((m.V.array() == r.V.array()).all()) << "OBJ must round-trip doubles exactly";
  EXPECT_EQ(info.polygons_read, 4u);
  EXPECT_EQ(info.polygons_triangulated, 0u);
  EXPECT_EQ(info.polygons_dropped, 0u);
}

TEST_F(MeshIoTest, PlyRoundTripIsExact) {
  const vt::TriMesh m = tetrahedron();
  std::string error;
  const std::string p = path("tet.PLY");  // extension is case-insensitive
  ASSERT_TRUE(vt::writeMesh(p, m, error)) << error;
  vt::TriMesh r;
  ASSERT_TRUE(vt::readMesh(p, r, error)) << error;
  expectSameTopology(m, r);
  EXPECT_TRUE((m.V.array() == r.V.array()).all()) << "PLY is written with double coordinates";
}

TEST_F(MeshIoTest, StlRoundTripWithinFloatPrecision) {
  // STL stores float32 corners per triangle; reading welds equal corners and numbers the
  // vertices by first appearance in the face list (here 0, 2, 1, 3), faces keep their order.
  const vt::TriMesh m = tetrahedron();
  std::string error;
  const std::string p = path("tet.stl");
  ASSERT_TRUE(vt::writeMesh(p, m, error)) << error;
  vt::TriMesh r;
  vt::MeshReadInfo info;
  ASSERT_TRUE(vt::readMesh(p, r, error, &info)) << error;
  ASSERT_EQ(r.V.rows(), 4);
  ASSERT_EQ(r.F.rows(), 4);
  EXPECT_EQ(info.polygons_read, 4u);
  for (Eigen::Index f = 0; f < m.F.rows(); ++f)
    for (int k = 0; k < 3; ++k)
      for (int d = 0; d < 3; ++d)
        EXPECT_EQ(r.V(r.F(f, k), d), static_cast<double>(static_cast<float>(m.V(m.F(f, k), d))))
            << "face " << f << " corner " << k;
  const int firstAppearance[4] = {0, 2, 1, 3};
  for (int i = 0; i < 4; ++i)
    EXPECT_NEAR((r.V.row(i) - m.V.row(firstAppearance[i])).norm(), 0.0, 1e-6) << i;
}

TEST_F(MeshIoTest, AsciiStlIsWeldedInOrderOfFirstAppearance) {
  const std::string p = writeText("quad.stl",
                                  "solid quad\n"
                                  "facet normal 0 0 1\n outer loop\n"
                                  "  vertex 0 0 0\n  vertex 1 0 0\n  vertex 1 1 0\n"
                                  " endloop\nendfacet\n"
                                  "facet normal 0 0 1\n outer loop\n"
                                  "  vertex 0 0 0\n  vertex 1 1 0\n  vertex 0 1 0\n"
                                  " endloop\nendfacet\n"
                                  "endsolid quad\n");
  vt::TriMesh r;
  std::string error;
  ASSERT_TRUE(vt::readMesh(p, r, error)) << error;
  ASSERT_EQ(r.V.rows(), 4);
  ASSERT_EQ(r.F.rows(), 2);
  EXPECT_EQ(r.V.row(2), Eigen::RowVector3d(1, 1, 0));
  EXPECT_EQ(r.V.row(3), Eigen::RowVector3d(0, 1, 0));
  EXPECT_EQ(r.F.row(0), Eigen::RowVector3i(0, 1, 2));
  EXPECT_EQ(r.F.row(1), Eigen::RowVector3i(0, 2, 3));
}

TEST_F(MeshIoTest, ObjNgonsSlashFormsCommentsAndNegativeIndices) {
  const std::string p = writeText("ngon.obj",
                                  "# a quad, a pentagon, a relative triangle and a 2-gon\r\n"
                                  "mtllib none.mtl\n"
                                  "o thing\n"
                                  "v 0 0 0\n"
                                  "v 1 0 0\n"
                                  "v 1 1 0 1.0\n"  // optional w
                                  "v 0 1 0 0.5 0.5 0.5\n"  // vertex colour
                                  "vt 0 0\n"
                                  "vn 0 0 1\n"
                                  "\tv  +0.5   2   -1e-3  \r\n"
                                  "g group1\n"
                                  "usemtl skin\n"
                                  "s off\n"
                                  "f 1/1/1 2/1/1 3/1/1 4/1/1\n"
                                  "f 1//1 2//1 3//1 5//1 4//1\r\n"
                                  "f -5/1 -4/1 -1/1   \n"
                                  "f 1 2\n"
                                  "l 1 2 3\n");
  vt::TriMesh r;
  vt::MeshReadInfo info;
  std::string error;
  ASSERT_TRUE(vt::readMesh(p, r, error, &info)) << error;
  ASSERT_EQ(r.V.rows(), 5);
  EXPECT_EQ(r.V.row(4), Eigen::RowVector3d(0.5, 2, -1e-3));
  EXPECT_EQ(r.V.row(2), Eigen::RowVector3d(1, 1, 0));
  ASSERT_EQ(r.F.rows(), 2 + 3 + 1);
  EXPECT_EQ(info.polygons_read, 4u);
  EXPECT_EQ(info.polygons_triangulated, 2u);
  EXPECT_EQ(info.polygons_dropped, 1u);
  // Fan around the first corner.
  EXPECT_EQ(r.F.row(0), Eigen::RowVector3i(0, 1, 2));
  EXPECT_EQ(r.F.row(1), Eigen::RowVector3i(0, 2, 3));
  EXPECT_EQ(r.F.row(2), Eigen::RowVector3i(0, 1, 2));
  EXPECT_EQ(r.F.row(3), Eigen::RowVector3i(0, 2, 4));
  EXPECT_EQ(r.F.row(4), Eigen::RowVector3i(0, 4, 3));
  EXPECT_EQ(r.F.row(5), Eigen::RowVector3i(0, 1, 4));
}

TEST_F(MeshIoTest, PlyPolygonsAreTriangulatedAndCounted) {
  const std::string p = writeText("ngon.ply",
                                  "ply\nformat ascii 1.0\n"
                                  "element vertex 5\n"
                                  "property float x\nproperty float y\nproperty float z\n"
                                  "property uchar red\nproperty uchar green\nproperty uchar blue\n"
                                  "element face 3\n"
                                  "property list uchar uint vertex_indices\n"
                                  "end_header\n"
                                  "0 0 0 255 0 0\n1 0 0 255 0 0\n1 1 0 255 0 0\n0 1 0 255 0 0\n"
                                  "0.5 2 0 255 0 0\n"
                                  "4 0 1 2 3\n3 0 2 4\n2 0 1\n");
  vt::TriMesh r;
  vt::MeshReadInfo info;
  std::string error;
  ASSERT_TRUE(vt::readMesh(p, r, error, &info)) << error;
  EXPECT_EQ(r.V.rows(), 5);
  ASSERT_EQ(r.F.rows(), 3);
  EXPECT_EQ(r.F.row(1), Eigen::RowVector3i(0, 2, 3));
  EXPECT_EQ(r.V.row(4), Eigen::RowVector3d(0.5, 2, 0));
  EXPECT_EQ(info.polygons_read, 3u);
  EXPECT_EQ(info.polygons_triangulated, 1u);
  EXPECT_EQ(info.polygons_dropped, 1u);
}

TEST_F(MeshIoTest, ObjIndexErrorsNameFileAndLine) {
  struct Case {
    const char* name;
    const char* body;
    const char* expect;  // substring of the message
  };
  const Case cases[] = {
      {"too_big.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 4\n", "line 4"},
      {"too_negative.obj", "v 0 0 0\nv 1 0 0\nf -1 -2 -3\nv 0 1 0\n", "line 3"},
      {"zero.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 0 1 2\n", "index 0"},
      {"garbage_index.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 x\n", "bad face index"},
      {"short_vertex.obj", "v 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n", "line 1"},
      {"bad_number.obj", "v 0 0 zero\nv 1 0 0\nv 0 1 0\nf 1 2 3\n", "bad vertex coordinate"},
      {"nan.obj", "v 0 0 nan\nv 1 0 0\nv 0 1 0\nf 1 2 3\n", "non-finite"},
      {"no_faces.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\n", "no usable triangle"},
      {"only_2gons.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2\n", "no usable triangle"},
      {"comments_only.obj", "# nothing\n", "no vertices"},
  };
  for (const Case& c : cases) {
    const std::string p = writeText(c.name, c.body);
    vt::TriMesh r;
    std::string error;
    EXPECT_FALSE(vt::readMesh(p, r, error)) << c.name;
    EXPECT_NE(error.find(p), std::string::npos) << c.name << ": " << error;
    EXPECT_NE(error.find(c.expect), std::string::npos) << c.name << ": " << error;
  }
}

TEST_F(MeshIoTest, PlyIndexOutOfRangeFails) {
  const std::string p = writeText("bad.ply",
                                  "ply\nformat ascii 1.0\nelement vertex 3\n"
                                  "property double x\nproperty double y\nproperty double z\n"
                                  "element face 1\nproperty list uchar int vertex_indices\nend_header\n"
                                  "0 0 0\n1 0 0\n0 1 0\n3 0 1 7\n");
  vt::TriMesh r;
  std::string error;
  EXPECT_FALSE(vt::readMesh(p, r, error));
  EXPECT_NE(error.find(p), std::string::npos) << error;
  EXPECT_NE(error.find("vertex 7"), std::string::npos) << error;
}

TEST_F(MeshIoTest, MissingFileNamesTheFile) {
  for (const char* name : {"missing.obj", "missing.ply", "missing.stl"}) {
    const std::string p = dir_ + "/" + name;
    vt::TriMesh r;
    std::string error;
    EXPECT_FALSE(vt::readMesh(p, r, error));
    EXPECT_NE(error.find(p), std::string::npos) << error;
    EXPECT_NE(error.find("no such file"), std::string::npos) << error;
  }
}

TEST_F(MeshIoTest, UnknownExtensionFails) {
  const vt::TriMesh m = tetrahedron();
  for (const char* name : {"mesh.off", "mesh", "dir.obj/mesh"}) {
    const std::string p = path(name);
    std::string error;
    EXPECT_FALSE(vt::writeMesh(p, m, error)) << name;
    EXPECT_NE(error.find("extension"), std::string::npos) << error;
    vt::TriMesh r;
    error.clear();
    EXPECT_FALSE(vt::readMesh(p, r, error)) << name;
    EXPECT_NE(error.find(p), std::string::npos) << error;
    EXPECT_NE(error.find("extension"), std::string::npos) << error;
  }
}

TEST_F(MeshIoTest, EmptyFileFails) {
  for (const char* name : {"empty.obj", "empty.ply", "empty.stl"}) {
    const std::string p = writeText(name, "");
    vt::TriMesh r;
    std::string error;
    EXPECT_FALSE(vt::readMesh(p, r, error)) << name;
    EXPECT_NE(error.find(p), std::string::npos) << error;
    EXPECT_NE(error.find("empty"), std::string::npos) << error;
  }
}

TEST_F(MeshIoTest, GarbageFilesFailWithoutTouchingTheMesh) {
  vt::TriMesh r = tetrahedron();
  for (const char* name : {"garbage.ply", "garbage.stl"}) {
    const std::string p = writeText(name, "this is not a mesh\n");
    std::string error;
    EXPECT_FALSE(vt::readMesh(p, r, error)) << name;
    EXPECT_NE(error.find(p), std::string::npos) << error;
  }
  EXPECT_EQ(r.V.rows(), 4);  // left as it was
  EXPECT_EQ(r.F.rows(), 4);
}

TEST_F(MeshIoTest, WriteRejectsBadIndicesAndUnwritablePaths) {
  vt::TriMesh m = tetrahedron();
  m.F(2, 1) = 4;
  std::string error;
  EXPECT_FALSE(vt::writeMesh(path("bad.obj"), m, error));
  EXPECT_NE(error.find("face 2"), std::string::npos) << error;

  const vt::TriMesh good = tetrahedron();
  for (const char* name : {"/no/such/dir/x.obj", "/no/such/dir/x.ply", "/no/such/dir/x.stl"}) {
    const std::string p = dir_ + name;
    error.clear();
    EXPECT_FALSE(vt::writeMesh(p, good, error)) << name;
    EXPECT_NE(error.find(p), std::string::npos) << error;
  }
}

TEST_F(MeshIoTest, VertexOrderAndUnusedVerticesSurviveObjAndPly) {
  // Vertex 1 is unused and vertices are referenced out of order.
  vt::TriMesh m;
  m.V.resize(5, 3);
  m.V << 0, 0, 0, 9, 9, 9, 1, 0, 0, 0, 1, 0, 0, 0, 1;
  m.F.resize(2, 3);
  m.F << 4, 3, 2, 0, 2, 3;
  for (const char* name : {"order.obj", "order.ply"}) {
    const std::string p = path(name);
    std::string error;
    ASSERT_TRUE(vt::writeMesh(p, m, error)) << error;
    vt::TriMesh r;
    ASSERT_TRUE(vt::readMesh(p, r, error)) << error;
    expectSameTopology(m, r);
    EXPECT_TRUE((m.V.array() == r.V.array()).all()) << name;
  }
}

// Found by fuzz_mesh_io: a binary STL whose header declares 538,969,088 triangles in a 325-byte
// file. vtkSTLReader allocates for the declared count before reading (19 GB here) and the
// process ran out of memory; readMesh now refuses such a file before VTK sees it.
TEST_F(MeshIoTest, BinaryStlDeclaringMoreTrianglesThanItHoldsIsRefused) {
  std::string bytes(80, '\0');
  bytes.replace(0, 40, "Visualization Toolkit generated SLA File");
  const std::uint32_t declared = 0x20200400u;
  for (int k = 0; k < 4; ++k) bytes += static_cast<char>((declared >> (8 * k)) & 0xFF);
  bytes += std::string(2 * 50, '\0');  // two (all-zero) triangles
  const std::string p = writeText("bogus_count.stl", bytes);
  vt::TriMesh r;
  std::string error;
  EXPECT_FALSE(vt::readMesh(p, r, error));
  EXPECT_NE(error.find("declares 538969088 triangles but the file (184 bytes) holds 2"), std::string::npos) << error;
  // A count below what the file holds is what VTK corrects silently: still read.
  const vt::TriMesh tet = tetrahedron();
  const std::string q = path("low_count.stl");
  ASSERT_TRUE(vt::writeMesh(q, tet, error)) << error;
  {
    std::fstream f(q, std::ios::in | std::ios::out | std::ios::binary);
    f.seekp(80);
    const char one[4] = {1, 0, 0, 0};
    f.write(one, 4);
  }
  ASSERT_TRUE(vt::readMesh(q, r, error)) << error;
  EXPECT_EQ(r.F.rows(), 4);
}

TEST_F(MeshIoTest, SizeLimitsAreCheckedBeforeReading) {
  vt::MeshLimits small;
  small.max_vertices = 3;
  small.max_faces = 3;
  vt::TriMesh r;
  std::string error;
  // OBJ: the fourth vertex is refused where it is read.
  const std::string obj = writeText("four.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 2 3\n");
  EXPECT_FALSE(vt::readMesh(obj, r, error, nullptr, small));
  EXPECT_NE(error.find("line 4: the mesh has 4 vertices, over the limit of 3 vertices"), std::string::npos) << error;
  // PLY: refused from the header, with the default limits, before PCL allocates the cloud.
  const std::string ply = writeText("huge.ply",
                                    "ply\nformat binary_little_endian 1.0\nelement vertex 2000001\n"
                                    "property float x\nproperty float y\nproperty float z\nend_header\n");
  EXPECT_FALSE(vt::readMesh(ply, r, error));
  EXPECT_NE(error.find("2000001 vertices, over the limit of 2000000 vertices"), std::string::npos) << error;
  // PLY whose header promises more than the file holds.
  const std::string shortPly = writeText("short.ply",
                                         "ply\nformat binary_little_endian 1.0\nelement vertex 100\n"
                                         "property double x\nproperty double y\nproperty double z\n"
                                         "element face 10\nproperty list uchar int vertex_indices\nend_header\n" +
                                             std::string(24, '\0'));
  EXPECT_FALSE(vt::readMesh(shortPly, r, error));
  EXPECT_NE(error.find("(at least 2410 bytes of data), but only 24 bytes follow it"), std::string::npos) << error;
  // STL: the tetrahedron's 4 triangles over a limit of 3.
  const std::string stl = path("tet.stl");
  ASSERT_TRUE(vt::writeMesh(stl, tetrahedron(), error)) << error;
  EXPECT_FALSE(vt::readMesh(stl, r, error, nullptr, small));
  EXPECT_NE(error.find("holds 4 triangles, over the limit of 3 triangles"), std::string::npos) << error;
}

// Found by fuzz_mesh_io: a PLY header whose "element face" line is misspelt, so that the face
// list property belongs to the vertex element. pcl::PLYReader hit assert(false) in
// vertexListPropertyContentCallback and aborted the process. PLY is now read by our own reader,
// which refuses unknown header keywords and reads (or skips) any property layout.
TEST_F(MeshIoTest, PlyHeaderOddLayoutsAreReadOrRefusedNeverCrash) {
  const std::string head = "ply\nformat ascii 1.0\nelement vertex 4\nproperty double x\nproperty double y\n"
                           "property double z\n";
  const std::string verts = "0 0 0\n1 0 0\n0 1 0\n0 0 1\n";
  struct Case {
    const char* name;
    std::string text;
    bool ok;
    const char* expect;  // substring of the error when !ok
  };
  const Case cases[] = {
      {"typo.ply", head + "elemenz face 1\nproperty list uchar int vertex_indices\nend_header\n" + verts + "3 0 1 2\n",
       false, "PLY header line 7: unknown keyword 'elemenz'"},
      {"list_on_vertex.ply",
       "ply\nformat ascii 1.0\nelement vertex 4\nproperty double x\nproperty double y\nproperty double z\n"
       "property list uchar int tags\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n"
       "0 0 0 0\n1 0 0 2 7 8\n0 1 0 1 5\n0 0 1 0\n3 0 1 2\n",
       true, ""},
      {"face_colour_and_other_element.ply",
       head + "element edge 1\nproperty int vertex1\nproperty int vertex2\n"
              "element face 1\nproperty uchar red\nproperty list uchar int vertex_indices\nend_header\n" +
           verts + "0 1\n200 3 0 1 2\n",
       true, ""},
      {"float_indices.ply", head + "element face 1\nproperty list uchar float vertex_indices\nend_header\n" + verts +
                                "3 0 1 2\n",
       false, "holds non-integer values"},
      {"negative_index.ply", head + "element face 1\nproperty list uchar int vertex_indices\nend_header\n" + verts +
                                 "3 0 -1 2\n",
       false, "refers to vertex -1"},
      {"negative_length.ply", head + "element face 1\nproperty list char int vertex_indices\nend_header\n" + verts +
                                  "-3 0 1 2\n",
       false, "negative list length -3"},
      {"long_list.ply", head + "element face 1\nproperty list uint int vertex_indices\nend_header\n" + verts +
                            "4000000000 0 1 2\n",
       false, "a list of 4000000000 items runs past the end of the file"},
      {"no_x.ply", "ply\nformat ascii 1.0\nelement vertex 1\nproperty float y\nend_header\n0\n", false,
       "no scalar 'x' property"},
      {"no_format.ply", "ply\nelement vertex 1\nproperty float x\nend_header\n0\n", false, "no 'format' line"},
      {"bad_type.ply", "ply\nformat ascii 1.0\nelement vertex 1\nproperty quad x\nend_header\n0\n", false,
       "unknown property type 'quad'"},
      {"nan.ply", head + "element face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 nan\n1 0 0\n0 1 0\n"
                         "0 0 1\n3 0 1 2\n",
       false, "non-finite vertex coordinate"},
      {"short_data.ply", head + "element face 2\nproperty list uchar int vertex_indices\nend_header\n" + verts +
                             "3 0 1 2\n3 0 1\n",
       false, "row 1: the data ends early"},
      {"twice.ply", head + "element vertex 1\nproperty float x\nend_header\n", false, "declared twice"},
  };
  for (const Case& c : cases) {
    const std::string p = writeText(c.name, c.text);
    vt::TriMesh r;
    std::string error;
    EXPECT_EQ(vt::readMesh(p, r, error), c.ok) << c.name << ": " << error;
    if (c.ok) {
      EXPECT_EQ(r.V.rows(), 4) << c.name;
      EXPECT_EQ(r.F.rows(), 1) << c.name;
    } else {
      EXPECT_NE(error.find(c.expect), std::string::npos) << c.name << ": " << error;
    }
  }
}

TEST_F(MeshIoTest, PlyBigEndianAndOtherScalarTypes) {
  // Binary big-endian: float x, y, z, an unused short, faces with ushort indices.
  std::string s = "ply\nformat binary_big_endian 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
                  "property float z\nproperty short q\nelement face 1\nproperty list uchar ushort vertex_indices\n"
                  "end_header\n";
  auto be = [&s](const void* p, std::size_t n) {
    const unsigned char* b = static_cast<const unsigned char*>(p);
    for (std::size_t i = 0; i < n; ++i) s += static_cast<char>(b[n - 1 - i]);  // host is little-endian
  };
  const float xyz[3][3] = {{0.5f, 0, 0}, {1, 2, 0}, {0, 0, -3}};
  for (const auto& v : xyz) {
    for (float c : v) be(&c, 4);
    const std::int16_t q = -7;
    be(&q, 2);
  }
  s += static_cast<char>(3);
  for (std::uint16_t i : {2, 0, 1}) be(&i, 2);
  const std::string p = writeText("be.ply", s);
  vt::TriMesh r;
  std::string error;
  ASSERT_TRUE(vt::readMesh(p, r, error)) << error;
  ASSERT_EQ(r.V.rows(), 3);
  EXPECT_EQ(r.V.row(1), Eigen::RowVector3d(1, 2, 0));
  EXPECT_EQ(r.V(2, 2), -3.0);
  EXPECT_EQ(r.F.row(0), Eigen::RowVector3i(2, 0, 1));
}
