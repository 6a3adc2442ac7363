// Mesh files: OBJ and PLY (own readers and writers), STL (PCL/VTK reader and writer, behind our
// own size checks). See mesh_io.h.
//
// Why not PCL for everything:
//  * pcl::io::loadOBJFile stores coordinates as float32, which would lose the precision the OBJ
//    writer keeps; the reader below parses doubles (std::from_chars) and is faster.
//  * pcl::io::savePLYFileBinary(PolygonMesh) only writes float32 x, y, z (and refuses FLOAT64
//    clouds); the writer below writes `property double`.
//  * pcl::io::loadPLYFile trusts the header: it allocates what it declares and asserts (aborts the
//    process) or writes past its buffer on layouts it does not expect; the reader below checks
//    every count and index against the limits and the file.
#include "virtual_tryon/core/io/mesh_io.h"

#include "virtual_tryon/core/io/point_records.h"

#include <pcl/PCLPointCloud2.h>
#include <pcl/PCLPointField.h>
#include <pcl/PolygonMesh.h>
#include <pcl/io/vtk_lib_io.h>

#include <sys/stat.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <limits>
#include <memory>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

namespace virtual_tryon {
namespace {

enum class Format { Obj, Ply, Stl, Unknown };

std::string extensionOf(const std::string& path) {
  const std::size_t slash = path.find_last_of('/');
  const std::size_t dot = path.find_last_of('.');
  if (dot == std::string::npos || (slash != std::string::npos && dot < slash)) return "";
  std::string ext = path.substr(dot);
  for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return ext;
}

Format formatOf(const std::string& path) {
  const std::string ext = extensionOf(path);
  if (ext == ".obj") return Format::Obj;
  if (ext == ".ply") return Format::Ply;
  if (ext == ".stl") return Format::Stl;
  return Format::Unknown;
}

std::string unknownFormatMessage(const std::string& path) {
  const std::string ext = extensionOf(path);
  return "mesh file '" + path + "': " +
         (ext.empty() ? std::string("has no extension")
                      : "unknown extension '" + ext + "'") +
         " (expected .obj, .ply or .stl)";
}

std::string fail(const std::string& path, const std::string& problem) {
  return "mesh file '" + path + "': " + problem;
}

struct FileCloser {
  void operator()(std::FILE* f) const {
    if (f) std::fclose(f);
  }
};
using FilePtr = std::unique_ptr<std::FILE, FileCloser>;

// Checks that `path` is an existing, readable, non-empty regular file. Run before handing the
// path to PCL, whose readers (VTK for STL) only print their complaints to stderr.
bool checkReadable(const std::string& path, std::string& error) {
  struct stat st;
  if (::stat(path.c_str(), &st) != 0) {
    error = fail(path, errno == ENOENT ? "no such file" : std::strerror(errno));
    return false;
  }
  if (S_ISDIR(st.st_mode)) {
    error = fail(path, "is a directory");
    return false;
  }
  FilePtr f(std::fopen(path.c_str(), "rb"));
  if (!f) {
    error = fail(path, std::string("cannot open: ") + std::strerror(errno));
    return false;
  }
  if (S_ISREG(st.st_mode) && st.st_size == 0) {
    error = fail(path, "file is empty");
    return false;
  }
  return true;
}

bool readWholeFile(const std::string& path, std::string& text, std::string& error) {
  FilePtr f(std::fopen(path.c_str(), "rb"));
  if (!f) {
    error = fail(path, std::string("cannot open: ") + std::strerror(errno));
    return false;
  }
  text.clear();
  char buf[1 << 16];
  std::size_t n;
  while ((n = std::fread(buf, 1, sizeof(buf), f.get())) > 0) text.append(buf, n);
  if (std::ferror(f.get())) {
    error = fail(path, "read error");
    return false;
  }
  return true;
}

// Appends the triangles of one polygon (fan around its first corner) to `tris`.
void addPolygon(const int* idx, std::size_t n, std::vector<int>& tris, MeshReadInfo& info) {
  ++info.polygons_read;
  if (n < 3) {
    ++info.polygons_dropped;
    return;
  }
  if (n > 3) ++info.polygons_triangulated;
  for (std::size_t k = 1; k + 1 < n; ++k) {
    tris.push_back(idx[0]);
    tris.push_back(idx[k]);
    tris.push_back(idx[k + 1]);
  }
}

bool finish(const std::string& path, std::vector<double>& coords, std::vector<int>& tris,
            TriMesh& mesh, std::string& error, const MeshLimits& limits) {
  const Eigen::Index nv = static_cast<Eigen::Index>(coords.size() / 3);
  const Eigen::Index nf = static_cast<Eigen::Index>(tris.size() / 3);
  const std::string tooBig = checkMeshSize(static_cast<std::uint64_t>(nv), static_cast<std::uint64_t>(nf),
                                           limits, "the mesh");
  if (!tooBig.empty()) {
    error = fail(path, tooBig);
    return false;
  }
  if (nv == 0) {
    error = fail(path, "no vertices");
    return false;
  }
  if (nf == 0) {
    error = fail(path, "has no faces (no usable triangle; " + std::to_string(nv) + " vertices)");
    return false;
  }
  mesh.V = Eigen::Map<const MatrixX3d>(coords.data(), nv, 3);
  mesh.F = Eigen::Map<const MatrixX3i>(tris.data(), nf, 3);
  return true;
}

// ----------------------------------------------------------------------------------------------
// OBJ reader. Reads `v x y z [w | r g b]` and `f` lines (`f a`, `f a/b`, `f a//c`, `f a/b/c`,
// negative = relative indices); everything else (vt, vn, g, o, s, usemtl, mtllib, l, p,
// comments) is ignored.

inline bool isSpace(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\f' || c == '\v'; }

inline const char* skipSpace(const char* p, const char* end) {
  while (p < end && isSpace(*p)) ++p;
  return p;
}

inline const char* tokenEnd(const char* p, const char* end) {
  while (p < end && !isSpace(*p)) ++p;
  return p;
}

bool parseDouble(const char* b, const char* e, double& value) {
  if (b < e && *b == '+') ++b;
  const auto r = std::from_chars(b, e, value);
  return r.ec == std::errc() && r.ptr == e;
}

// What readObj has read so far, line by line; `problem` says what is wrong on `line`.
struct ObjReader {
  ObjReader(const MeshLimits& l, MeshReadInfo& i) : limits(l), info(i) {}

  // Line `line`, [p, eol) without its '\n'.
  bool readLine(const char* p, const char* eol);
  // The rest of a `v` line, after the keyword: x, y, z (more coordinates are ignored).
  bool vertex(const char* t, const char* eol);
  // The rest of an `f` line, after the keyword.
  bool face(const char* t, const char* eol);
  // One corner of a face, [t, te), as a 0-based index appended to `poly`.
  bool faceIndex(const char* t, const char* te, long long nv);
  // After the last line: every positive index refers to a vertex of the file.
  bool checkMaxIndex();
  bool lineError(const std::string& what) {
    problem = what;
    return false;
  }

  const MeshLimits& limits;
  MeshReadInfo& info;
  std::vector<double> coords;
  std::vector<int> tris;
  std::vector<int> poly;
  std::size_t line = 0;
  long long maxIndex = -1;  // largest positive index seen (0-based) and where
  std::size_t maxIndexLine = 0;
  std::string problem;
};

bool ObjReader::readLine(const char* p, const char* eol) {
  const char* q = skipSpace(p, eol);
  if (q == eol || *q == '#') return true;
  const char* kw = q;
  const char* kwEnd = tokenEnd(q, eol);
  const std::size_t kwLen = static_cast<std::size_t>(kwEnd - kw);
  if (kwLen == 1 && kw[0] == 'v') return vertex(kwEnd, eol);
  if (kwLen == 1 && kw[0] == 'f') return face(kwEnd, eol);
  return true;
}

bool ObjReader::vertex(const char* t, const char* eol) {
  double xyz[3];
  for (int k = 0; k < 3; ++k) {
    t = skipSpace(t, eol);
    const char* te = tokenEnd(t, eol);
    if (t == te) return lineError("vertex with fewer than 3 coordinates");
    if (!parseDouble(t, te, xyz[k]))
      return lineError("bad vertex coordinate '" + std::string(t, te) + "'");
    if (!std::isfinite(xyz[k])) return lineError("non-finite vertex coordinate (NaN or Inf)");
    t = te;
  }
  if (coords.size() / 3 >= limits.max_vertices)
    return lineError(checkMeshSize(coords.size() / 3 + 1, 0, limits, "the mesh"));
  coords.insert(coords.end(), xyz, xyz + 3);
  return true;
}

bool ObjReader::face(const char* t, const char* eol) {
  poly.clear();
  const long long nv = static_cast<long long>(coords.size() / 3);
  t = skipSpace(t, eol);
  while (t < eol) {
    const char* te = tokenEnd(t, eol);
    if (!faceIndex(t, te, nv)) return false;
    t = skipSpace(te, eol);
  }
  if (poly.size() > 2 && tris.size() / 3 + (poly.size() - 2) > limits.max_faces)
    return lineError(checkMeshSize(0, tris.size() / 3 + (poly.size() - 2), limits, "the mesh"));
  addPolygon(poly.data(), poly.size(), tris, info);
  return true;
}

bool ObjReader::faceIndex(const char* t, const char* te, long long nv) {
  const char* slash = static_cast<const char*>(std::memchr(t, '/', static_cast<std::size_t>(te - t)));
  const char* ie = slash ? slash : te;
  const char* ib = t;
  if (ib < ie && *ib == '+') ++ib;
  long long v = 0;
  const auto r = std::from_chars(ib, ie, v);
  if (r.ec != std::errc() || r.ptr != ie)
    return lineError("bad face index '" + std::string(t, te) + "'");
  long long idx;
  if (v > 0) {
    idx = v - 1;  // checked against the final vertex count by checkMaxIndex
    if (idx > maxIndex) {
      maxIndex = idx;
      maxIndexLine = line;
    }
  } else if (v < 0) {
    idx = nv + v;  // relative to the vertices read so far
    if (idx < 0)
      return lineError("relative face index " + std::to_string(v) + " but only " +
                       std::to_string(nv) + " vertices before it");
  } else {
    return lineError("face index 0 (OBJ indices start at 1)");
  }
  if (idx > std::numeric_limits<int>::max()) return lineError("face index too large");
  poly.push_back(static_cast<int>(idx));
  return true;
}

bool ObjReader::checkMaxIndex() {
  const long long nv = static_cast<long long>(coords.size() / 3);
  if (maxIndex >= nv) {
    line = maxIndexLine;
    return lineError("face index " + std::to_string(maxIndex + 1) + " out of range: the file has " +
                     std::to_string(nv) + " vertices");
  }
  return true;
}

bool readObj(const std::string& path, TriMesh& mesh, std::string& error, MeshReadInfo& info,
             const MeshLimits& limits) {
  std::string text;
  if (!readWholeFile(path, text, error)) return false;

  ObjReader obj(limits, info);
  obj.coords.reserve(text.size() / 12);
  obj.tris.reserve(text.size() / 8);
  const char* p = text.data();
  const char* const end = p + text.size();
  bool ok = true;
  while (ok && p < end) {
    ++obj.line;
    const char* eol = static_cast<const char*>(std::memchr(p, '\n', static_cast<std::size_t>(end - p)));
    if (!eol) eol = end;
    ok = obj.readLine(p, eol);
    p = eol < end ? eol + 1 : end;
  }
  if (!ok || !obj.checkMaxIndex()) {
    error = fail(path, "line " + std::to_string(obj.line) + ": " + obj.problem);
    return false;
  }
  return finish(path, obj.coords, obj.tris, mesh, error, limits);
}

// ----------------------------------------------------------------------------------------------
// pcl::PolygonMesh -> TriMesh, reading x, y, z by name and offset (FLOAT32 or FLOAT64) with the
// point record reader of point_records.h.

static_assert(pcl::PCLPointField::FLOAT32 == kPointFloat32 && pcl::PCLPointField::FLOAT64 == kPointFloat64,
              "pcl::PCLPointField datatypes differ from point_records.h");

// The sizes of `pm` (its `n` points and the triangles its polygons make) against the limits and
// what a mesh can index.
bool checkPolygonMeshSize(const std::string& path, const pcl::PolygonMesh& pm, std::uint64_t n,
                          std::string& error, const MeshLimits& limits) {
  if (n == 0) {
    error = fail(path, "no vertices");
    return false;
  }
  std::uint64_t triangles = 0;
  for (const auto& poly : pm.polygons)
    if (poly.vertices.size() > 2) triangles += poly.vertices.size() - 2;
  const std::string tooBig = checkMeshSize(n, triangles, limits, "the mesh");
  if (!tooBig.empty()) {
    error = fail(path, tooBig);
    return false;
  }
  if (n > static_cast<std::uint64_t>(std::numeric_limits<int>::max()) ||
      triangles > static_cast<std::uint64_t>(std::numeric_limits<int>::max() / 3)) {
    error = fail(path, "too many vertices or triangles");
    return false;
  }
  return true;
}

// Finds the x, y and z fields of `cloud`, each FLOAT32 or FLOAT64 inside the point step.
bool findXyzFields(const std::string& path, const PointRecords& cloud, const PointRecordField* (&xyz)[3],
                   std::string& error) {
  const char* names[3] = {"x", "y", "z"};
  for (int k = 0; k < 3; ++k) {
    xyz[k] = cloud.field(names[k]);
    if (!xyz[k]) {
      error = fail(path, std::string("vertices have no '") + names[k] + "' field");
      return false;
    }
    switch (checkFloatField(*xyz[k], cloud.point_step)) {
      case FloatFieldProblem::NotFloat:
        error = fail(path, std::string("field '") + names[k] + "' is neither float32 nor float64");
        return false;
      case FloatFieldProblem::OutsidePointStep:
        error = fail(path, std::string("field '") + names[k] + "' lies outside the point step");
        return false;
      case FloatFieldProblem::None: break;
    }
  }
  return true;
}

// The polygons of `pm` as triangles (fan), each index checked against the `n` points.
bool polygonsToTriangles(const std::string& path, const pcl::PolygonMesh& pm, std::uint64_t n,
                         std::vector<int>& tris, std::string& error, MeshReadInfo& info) {
  tris.reserve(pm.polygons.size() * 3);
  std::vector<int> poly;
  for (std::size_t p = 0; p < pm.polygons.size(); ++p) {
    const auto& verts = pm.polygons[p].vertices;
    poly.resize(verts.size());
    for (std::size_t k = 0; k < verts.size(); ++k) {
      if (static_cast<std::uint64_t>(verts[k]) >= n) {
        error = fail(path, "polygon " + std::to_string(p) + " refers to vertex " +
                               std::to_string(verts[k]) + " but the file has " + std::to_string(n) +
                               " vertices");
        return false;
      }
      poly[k] = static_cast<int>(verts[k]);
    }
    addPolygon(poly.data(), poly.size(), tris, info);
  }
  return true;
}

bool polygonMeshToTriMesh(const std::string& path, const pcl::PolygonMesh& pm, TriMesh& mesh,
                          std::string& error, MeshReadInfo& info, const MeshLimits& limits) {
  const PointRecords cloud = viewPointRecords(pm.cloud);
  const std::uint64_t n = cloud.points();
  if (!checkPolygonMeshSize(path, pm, n, error, limits)) return false;
  if (cloud.is_bigendian) {
    error = fail(path, "big-endian point data is not supported");
    return false;
  }
  const PointRecordField* xyz[3];
  if (!findXyzFields(path, cloud, xyz, error)) return false;
  if (checkPointExtent(cloud) != PointExtentProblem::None) {
    error = fail(path, "point data shorter than the declared size");
    return false;
  }

  std::vector<double> coords(static_cast<std::size_t>(n) * 3);
  readFloatFields(cloud, xyz, 3, [&](std::uint64_t i, int k, double v) { coords[3 * i + k] = v; });
  std::vector<int> tris;
  if (!polygonsToTriangles(path, pm, n, tris, error, info)) return false;
  return finish(path, coords, tris, mesh, error, limits);
}

// ----------------------------------------------------------------------------------------------
// PLY: own reader (ASCII, binary little- and big-endian). Not PCL's: pcl::PLYReader asserts, or
// writes past its cloud buffer, on headers it does not expect (fuzz_mesh_io found an abort on a
// list property of the vertex element) and allocates whatever the header declares.

enum class PlyType { Int8, UInt8, Int16, UInt16, Int32, UInt32, Float32, Float64 };

bool hostIsLittleEndian();

bool plyType(const std::string& t, PlyType& out) {
  static const std::pair<const char*, PlyType> kTypes[] = {
      {"char", PlyType::Int8},     {"int8", PlyType::Int8},       {"uchar", PlyType::UInt8},
      {"uint8", PlyType::UInt8},   {"short", PlyType::Int16},     {"int16", PlyType::Int16},
      {"ushort", PlyType::UInt16}, {"uint16", PlyType::UInt16},   {"int", PlyType::Int32},
      {"int32", PlyType::Int32},   {"uint", PlyType::UInt32},     {"uint32", PlyType::UInt32},
      {"float", PlyType::Float32}, {"float32", PlyType::Float32}, {"double", PlyType::Float64},
      {"float64", PlyType::Float64}};
  for (const auto& [name, type] : kTypes)
    if (t == name) {
      out = type;
      return true;
    }
  return false;
}

std::size_t plySize(PlyType t) {
  switch (t) {
    case PlyType::Int8: case PlyType::UInt8: return 1;
    case PlyType::Int16: case PlyType::UInt16: return 2;
    case PlyType::Int32: case PlyType::UInt32: case PlyType::Float32: return 4;
    case PlyType::Float64: return 8;
  }
  return 8;
}

bool plyIsInteger(PlyType t) { return t != PlyType::Float32 && t != PlyType::Float64; }

struct PlyProperty {
  std::string name;
  PlyType type = PlyType::Float32;  // of the value, or of a list's items
  bool list = false;
  PlyType countType = PlyType::UInt8;
};

struct PlyElement {
  std::string name;
  std::uint64_t count = 0;
  std::vector<PlyProperty> properties;
};

// Reads values one by one from the data after the header.
class PlyData {
 public:
  PlyData(const char* p, const char* end, bool ascii, bool swap) : p_(p), end_(end), ascii_(ascii), swap_(swap) {}

  std::uint64_t remaining() const { return static_cast<std::uint64_t>(end_ - p_); }
  // Nothing but (for ASCII) white space is left.
  bool atEnd() {
    if (ascii_)
      while (p_ < end_ && (isSpace(*p_) || *p_ == '\n')) ++p_;
    return p_ == end_;
  }

  // One value of type t; false at the end of the data or on a token that is not such a number.
  bool value(PlyType t, double& v) {
    if (ascii_) {
      while (p_ < end_ && (isSpace(*p_) || *p_ == '\n')) ++p_;
      const char* b = p_;
      while (p_ < end_ && !isSpace(*p_) && *p_ != '\n') ++p_;
      if (b == p_) return false;
      if (plyIsInteger(t)) {
        long long i = 0;
        const auto r = std::from_chars(b, p_, i);
        if (r.ec != std::errc() || r.ptr != p_) return false;
        v = static_cast<double>(i);
        return true;
      }
      return parseDouble(b, p_, v);
    }
    const std::size_t n = plySize(t);
    if (remaining() < n) return false;
    unsigned char b[8];
    std::memcpy(b, p_, n);
    p_ += n;
    if (swap_) std::reverse(b, b + n);
    switch (t) {
      case PlyType::Int8: v = static_cast<std::int8_t>(b[0]); break;
      case PlyType::UInt8: v = b[0]; break;
      case PlyType::Int16: { std::int16_t x; std::memcpy(&x, b, 2); v = x; break; }
      case PlyType::UInt16: { std::uint16_t x; std::memcpy(&x, b, 2); v = x; break; }
      case PlyType::Int32: { std::int32_t x; std::memcpy(&x, b, 4); v = x; break; }
      case PlyType::UInt32: { std::uint32_t x; std::memcpy(&x, b, 4); v = x; break; }
      case PlyType::Float32: { float x; std::memcpy(&x, b, 4); v = x; break; }
      case PlyType::Float64: std::memcpy(&v, b, 8); break;
    }
    return true;
  }

 private:
  const char* p_;
  const char* end_;
  bool ascii_, swap_;
};

// A PLY header: its elements in file order and its format; the data starts at `dataStart`.
struct PlyHeader {
  std::vector<PlyElement> elements;
  std::string format;
  std::size_t dataStart = std::string::npos;
};

// The rest of an `element NAME COUNT` line (`words`, after the keyword; `line` the whole line).
bool plyElementLine(std::istringstream& words, const std::string& line, std::vector<PlyElement>& elements,
                    std::string& what) {
  PlyElement e;
  std::string count, extra;
  words >> e.name >> count >> extra;
  const auto r = std::from_chars(count.data(), count.data() + count.size(), e.count);
  if (e.name.empty() || r.ec != std::errc() || r.ptr != count.data() + count.size() || !extra.empty()) {
    what = "expected 'element NAME COUNT', got '" + line + "'";
    return false;
  }
  for (const PlyElement& o : elements)
    if (o.name == e.name) {
      what = "element '" + e.name + "' declared twice";
      return false;
    }
  elements.push_back(e);
  return true;
}

// The rest of a `property TYPE NAME` or `property list COUNT_TYPE TYPE NAME` line.
bool plyPropertyLine(std::istringstream& words, const std::string& line, std::vector<PlyElement>& elements,
                     std::string& what) {
  if (elements.empty()) {
    what = "property before any element";
    return false;
  }
  PlyProperty prop;
  std::string type, extra;
  words >> type;
  if (type == "list") {
    std::string countType;
    words >> countType >> type;
    prop.list = true;
    if (!plyType(countType, prop.countType) || !plyIsInteger(prop.countType)) {
      what = "list count type '" + countType + "' is not an integer type";
      return false;
    }
  }
  if (!plyType(type, prop.type)) {
    what = "unknown property type '" + type + "'";
    return false;
  }
  words >> prop.name >> extra;
  if (prop.name.empty() || !extra.empty()) {
    what = "expected 'property TYPE NAME', got '" + line + "'";
    return false;
  }
  elements.back().properties.push_back(prop);
  return true;
}

// One header line after the first ("ply"), without its line break; sets `done` at end_header.
bool plyHeaderLine(const std::string& line, PlyHeader& header, bool& done, std::string& what) {
  std::istringstream words(line);
  std::string key;
  words >> key;
  if (key == "end_header") {
    done = true;
    return true;
  }
  if (key.empty() || key == "comment" || key == "obj_info") return true;
  if (key == "format") {
    std::string version;
    words >> header.format >> version;
    const std::string& format = header.format;
    if (format != "ascii" && format != "binary_little_endian" && format != "binary_big_endian") {
      what = "unknown format '" + format + "' (ascii, binary_little_endian or binary_big_endian)";
      return false;
    }
    return true;
  }
  if (key == "element") return plyElementLine(words, line, header.elements, what);
  if (key == "property") return plyPropertyLine(words, line, header.elements, what);
  what = "unknown keyword '" + key + "'";
  return false;
}

// The header: the lines of `text` up to "end_header".
bool parsePlyHeader(const std::string& path, const std::string& text, PlyHeader& header, std::string& error) {
  std::size_t pos = 0, lineNo = 0;
  while (pos < text.size()) {
    std::size_t nl = text.find('\n', pos);
    if (nl == std::string::npos) nl = text.size();
    std::string line = text.substr(pos, nl - pos);
    pos = nl + 1;
    ++lineNo;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (lineNo == 1) continue;  // "ply"
    bool done = false;
    std::string what;
    if (!plyHeaderLine(line, header, done, what)) {
      error = fail(path, "PLY header line " + std::to_string(lineNo) + ": " + what);
      return false;
    }
    if (done) {
      header.dataStart = std::min(pos, text.size());
      break;
    }
  }
  if (header.dataStart == std::string::npos) {
    error = fail(path, "PLY header has no 'end_header' line");
    return false;
  }
  if (header.format.empty()) {
    error = fail(path, "PLY header has no 'format' line");
    return false;
  }
  return true;
}

// The element called `name`, or nullptr (names are unique).
const PlyElement* plyElement(const PlyHeader& header, const char* name) {
  for (const PlyElement& e : header.elements)
    if (e.name == name) return &e;
  return nullptr;
}

// Sizes before anything is allocated: the declared counts (`nv` vertices, `nf` faces) against
// the limits, then against what the `body` bytes after the header can hold.
bool checkPlySizes(const std::string& path, const PlyHeader& header, std::uint64_t nv, std::uint64_t nf,
                   std::uint64_t body, const MeshLimits& limits, std::string& error) {
  for (const PlyElement& e : header.elements)
    if (e.count > limits.max_vertices + limits.max_faces) {
      error = fail(path, "PLY header declares " + std::to_string(e.count) + " '" + e.name +
                             "' elements, over the limits (MeshLimits)");
      return false;
    }
  const std::string tooBig = checkMeshSize(nv, nf, limits, "the PLY header: the mesh");
  if (!tooBig.empty()) {
    error = fail(path, tooBig);
    return false;
  }
  const bool ascii = header.format == "ascii";
  std::uint64_t needed = 0;  // counts are within the limits here: no overflow
  for (const PlyElement& e : header.elements)
    for (const PlyProperty& prop : e.properties)
      needed += e.count * (ascii ? 2 : plySize(prop.list ? prop.countType : prop.type));
  if (ascii && needed > 0) needed -= 1;  // the last value needs no separator
  if (needed > body) {
    error = fail(path, "PLY header declares " + std::to_string(nv) + " vertices and " + std::to_string(nf) +
                           " faces (at least " + std::to_string(needed) + " bytes of data), but only " +
                           std::to_string(body) + " bytes follow it");
    return false;
  }
  return true;
}

// The indices of the first scalar x, y and z properties of the vertex element.
bool findPlyXyz(const std::string& path, const PlyElement& vertexElement, int (&xyz)[3], std::string& error) {
  for (std::size_t k = 0; k < vertexElement.properties.size(); ++k) {
    const PlyProperty& prop = vertexElement.properties[k];
    for (int c = 0; c < 3; ++c)
      if (prop.name == std::string(1, static_cast<char>('x' + c)) && !prop.list && xyz[c] < 0)
        xyz[c] = static_cast<int>(k);
  }
  for (int c = 0; c < 3; ++c)
    if (xyz[c] < 0) {
      error = fail(path, std::string("PLY vertex element has no scalar '") + static_cast<char>('x' + c) +
                             "' property");
      return false;
    }
  return true;
}

// Reads the rows of the data after the header: the vertices' x, y, z into `coords`, the faces'
// polygons (from their first `vertex_indices` / `vertex_index` list) as triangles into `tris`;
// everything else is read and skipped. `problem` says what is wrong in the row.
struct PlyRows {
  PlyRows(PlyData& d, bool a, std::uint64_t n, const int (&c)[3], const MeshLimits& l, MeshReadInfo& i)
      : data(d), ascii(a), nv(n), xyz{c[0], c[1], c[2]}, limits(l), info(i) {}

  // Row `row` of element `e`.
  bool read(const PlyElement& e, std::uint64_t row, bool isVertex, bool isFace);
  // A list property of row `row`; its items are the row's polygon when `isFace`, no polygon was
  // read yet (`facePolygon`, then set) and the property is the vertex indices.
  bool list(const PlyProperty& prop, std::uint64_t row, bool isFace, bool& facePolygon);
  bool dataError(const std::string& what) {
    problem = what;
    return false;
  }

  PlyData& data;
  const bool ascii;
  const std::uint64_t nv;
  const int xyz[3];
  const MeshLimits& limits;
  MeshReadInfo& info;
  std::vector<double> coords;
  std::vector<int> tris;
  std::vector<int> poly;
  std::string problem;
};

bool PlyRows::read(const PlyElement& e, std::uint64_t row, bool isVertex, bool isFace) {
  double xyzRow[3] = {0, 0, 0};
  bool facePolygon = false;
  for (std::size_t k = 0; k < e.properties.size(); ++k) {
    const PlyProperty& prop = e.properties[k];
    if (prop.list) {
      if (!list(prop, row, isFace, facePolygon)) return false;
      continue;
    }
    double v = 0;
    if (!data.value(prop.type, v))
      return dataError(data.atEnd() ? "the data ends early" : "bad value for '" + prop.name + "'");
    if (isVertex)
      for (int c = 0; c < 3; ++c)
        if (static_cast<int>(k) == xyz[c]) xyzRow[c] = v;
  }
  if (isVertex) {
    if (!std::isfinite(xyzRow[0]) || !std::isfinite(xyzRow[1]) || !std::isfinite(xyzRow[2]))
      return dataError("non-finite vertex coordinate (NaN or Inf)");
    coords.insert(coords.end(), xyzRow, xyzRow + 3);
  }
  if (facePolygon) {
    if (poly.size() > 2 && tris.size() / 3 + (poly.size() - 2) > limits.max_faces)
      return dataError(checkMeshSize(0, tris.size() / 3 + (poly.size() - 2), limits, "the mesh"));
    addPolygon(poly.data(), poly.size(), tris, info);
  }
  return true;
}

bool PlyRows::list(const PlyProperty& prop, std::uint64_t row, bool isFace, bool& facePolygon) {
  double count = 0;
  if (!data.value(prop.countType, count))
    return dataError(data.atEnd() ? "the data ends early" : "bad list length for '" + prop.name + "'");
  if (count < 0) return dataError("negative list length " + std::to_string(static_cast<long long>(count)));
  const std::uint64_t n = static_cast<std::uint64_t>(count);
  const std::uint64_t itemBytes = ascii ? 1 : plySize(prop.type);
  if (n * itemBytes > data.remaining())
    return dataError("a list of " + std::to_string(n) + " items runs past the end of the file");
  const bool indices =
      isFace && !facePolygon && (prop.name == "vertex_indices" || prop.name == "vertex_index");
  if (indices && !plyIsInteger(prop.type))
    return dataError("'" + prop.name + "' holds non-integer values");
  if (indices) poly.resize(static_cast<std::size_t>(n));
  double v = 0;
  for (std::uint64_t i = 0; i < n; ++i) {
    if (!data.value(prop.type, v))
      return dataError(data.atEnd() ? "the data ends early" : "bad list item in '" + prop.name + "'");
    if (!indices) continue;
    if (v < 0 || v >= static_cast<double>(nv))
      return dataError("polygon " + std::to_string(row) + " refers to vertex " +
                       std::to_string(static_cast<long long>(v)) + " but the file has " + std::to_string(nv) +
                       " vertices");
    poly[static_cast<std::size_t>(i)] = static_cast<int>(v);
  }
  if (indices) facePolygon = true;
  return true;
}

bool readPly(const std::string& path, TriMesh& mesh, std::string& error, MeshReadInfo& info,
             const MeshLimits& limits) {
  std::string text;
  if (!readWholeFile(path, text, error)) return false;
  if (text.compare(0, 3, "ply") != 0 || (text.size() > 3 && text[3] != '\n' && text[3] != '\r')) {
    error = fail(path, "not a PLY file (it does not start with a 'ply' line)");
    return false;
  }
  PlyHeader header;
  if (!parsePlyHeader(path, text, header, error)) return false;
  const bool ascii = header.format == "ascii";
  const PlyElement* vertexElement = plyElement(header, "vertex");
  const PlyElement* faceElement = plyElement(header, "face");
  const std::uint64_t nv = vertexElement ? vertexElement->count : 0;
  const std::uint64_t nf = faceElement ? faceElement->count : 0;
  if (!checkPlySizes(path, header, nv, nf, text.size() - header.dataStart, limits, error)) return false;
  if (!vertexElement) {
    error = fail(path, "no vertices (the PLY header has no 'vertex' element)");
    return false;
  }
  int xyz[3] = {-1, -1, -1};
  if (!findPlyXyz(path, *vertexElement, xyz, error)) return false;

  // Data.
  const bool hostLittle = hostIsLittleEndian();
  const bool swap = !ascii && ((header.format == "binary_little_endian") != hostLittle);
  PlyData data(text.data() + header.dataStart, text.data() + text.size(), ascii, swap);
  PlyRows rows(data, ascii, nv, xyz, limits, info);
  rows.coords.reserve(static_cast<std::size_t>(3 * nv));
  for (const PlyElement& e : header.elements) {
    const bool isVertex = &e == vertexElement, isFace = &e == faceElement;
    for (std::uint64_t row = 0; row < e.count; ++row)
      if (!rows.read(e, row, isVertex, isFace)) {
        error = fail(path, "PLY element '" + e.name + "' row " + std::to_string(row) + ": " + rows.problem);
        return false;
      }
  }
  return finish(path, rows.coords, rows.tris, mesh, error, limits);
}

// Whether VTK's vtkSTLReader will read `head` (the file's first up to 256 bytes) as binary STL:
// it asks vtksys::SystemTools::DetectFileType, which calls a file binary when 5 % or more of those
// bytes are not text (printable ASCII, '\n', '\r', '\t'). We err towards binary (4 %).
bool vtkReadsAsBinary(const unsigned char* head, std::size_t n) {
  if (n == 0) return false;
  std::size_t text = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const unsigned char c = head[i];
    text += (c >= 0x20 && c <= 0x7E) || c == '\n' || c == '\r' || c == '\t';
  }
  return static_cast<double>(n - text) / static_cast<double>(n) >= 0.04;
}

// Checks an STL file before VTK reads it. Binary STL is an 80-byte header, a triangle count and
// 50 bytes per triangle; vtkSTLReader allocates for max(declared count, count from the file size)
// before reading, so a binary file whose header declares more triangles than it holds is refused
// here (4 bytes could otherwise ask for 2^31 triangles). Then the triangle count (ASCII: at most
// one per 60 bytes; a facet takes well over that) is checked against `limits`.
bool checkStlSize(const std::string& path, const MeshLimits& limits, std::string& error) {
  struct stat st;
  if (::stat(path.c_str(), &st) != 0) {
    error = fail(path, std::strerror(errno));
    return false;
  }
  const std::uint64_t size = static_cast<std::uint64_t>(st.st_size);
  FilePtr f(std::fopen(path.c_str(), "rb"));
  if (!f) {
    error = fail(path, std::string("cannot open: ") + std::strerror(errno));
    return false;
  }
  unsigned char head[256] = {0};
  const std::size_t got = std::fread(head, 1, sizeof head, f.get());
  std::uint32_t declared = 0;
  if (got >= 84)
    declared = static_cast<std::uint32_t>(head[80]) | static_cast<std::uint32_t>(head[81]) << 8 |
               static_cast<std::uint32_t>(head[82]) << 16 | static_cast<std::uint32_t>(head[83]) << 24;
  const std::uint64_t held = size >= 84 ? (size - 84) / 50 : 0;
  const bool exact = got >= 84 && size == 84 + 50 * static_cast<std::uint64_t>(declared);
  const bool binary = exact || vtkReadsAsBinary(head, got);
  std::uint64_t triangles = size / 60;  // ASCII
  if (binary) {
    if (got < 84) {
      error = fail(path, "binary STL of " + std::to_string(size) + " bytes is shorter than its 84-byte header");
      return false;
    }
    if (declared > held && declared <= static_cast<std::uint32_t>(std::numeric_limits<int>::max())) {
      error = fail(path, "binary STL header declares " + std::to_string(declared) + " triangles but the file (" +
                             std::to_string(size) + " bytes) holds " + std::to_string(held) +
                             " (84 bytes of header, 50 per triangle)");
      return false;
    }
    triangles = held;
  }
  if (triangles > limits.max_faces) {
    error = fail(path, "STL file of " + std::to_string(size) + " bytes holds " +
                           (binary ? std::string("") : std::string("up to ")) + std::to_string(triangles) +
                           " triangles, over the limit of " + std::to_string(limits.max_faces) +
                           " triangles (MeshLimits::max_faces)");
    return false;
  }
  return true;
}

bool readStl(const std::string& path, TriMesh& mesh, std::string& error, MeshReadInfo& info,
             const MeshLimits& limits) {
  if (!checkStlSize(path, limits, error)) return false;
  // VTK's vtkSTLReader (behind PCL) merges exactly-equal corner coordinates into one vertex,
  // numbered in order of first appearance, and drops triangles that become degenerate by it.
  pcl::PolygonMesh pm;
  if (pcl::io::loadPolygonFileSTL(path, pm) <= 0) {
    error = fail(path, "PCL/VTK could not read it as STL (or it holds no triangle)");
    return false;
  }
  return polygonMeshToTriMesh(path, pm, mesh, error, info, limits);
}

// ----------------------------------------------------------------------------------------------
// Writers.

bool checkIndices(const std::string& path, const TriMesh& mesh, std::string& error) {
  const Eigen::Index n = mesh.V.rows();
  for (Eigen::Index f = 0; f < mesh.F.rows(); ++f)
    for (int k = 0; k < 3; ++k)
      if (mesh.F(f, k) < 0 || mesh.F(f, k) >= n) {
        error = fail(path, "not written: face " + std::to_string(f) + " has vertex index " +
                               std::to_string(mesh.F(f, k)) + " outside [0, " + std::to_string(n) + ")");
        return false;
      }
  return true;
}

bool writeBuffer(const std::string& path, const std::string& buf, std::string& error) {
  std::FILE* f = std::fopen(path.c_str(), "wb");
  if (!f) {
    error = fail(path, std::string("cannot open for writing: ") + std::strerror(errno));
    return false;
  }
  const std::size_t written = std::fwrite(buf.data(), 1, buf.size(), f);
  const bool ok = written == buf.size() && !std::ferror(f);
  if (std::fclose(f) != 0 || !ok) {
    error = fail(path, std::string("write failed: ") + std::strerror(errno));
    return false;
  }
  return true;
}

// Shortest decimal form that reads back to exactly the same double.
inline void appendDouble(std::string& s, double v) {
  char buf[32];
  const auto r = std::to_chars(buf, buf + sizeof buf, v);
  s.append(buf, r.ptr);
}

inline void appendInt(std::string& s, long long v) {
  char buf[24];
  const auto r = std::to_chars(buf, buf + sizeof buf, v);
  s.append(buf, r.ptr);
}

bool writeObj(const std::string& path, const TriMesh& mesh, std::string& error) {
  std::string s;
  s.reserve(static_cast<std::size_t>(mesh.V.rows()) * 40 + static_cast<std::size_t>(mesh.F.rows()) * 24 + 128);
  s += "# virtual_tryon: ";
  appendInt(s, mesh.V.rows());
  s += " vertices, ";
  appendInt(s, mesh.F.rows());
  s += " triangles\n";
  for (Eigen::Index i = 0; i < mesh.V.rows(); ++i) {
    s += 'v';
    for (int k = 0; k < 3; ++k) {
      s += ' ';
      appendDouble(s, mesh.V(i, k));
    }
    s += '\n';
  }
  for (Eigen::Index f = 0; f < mesh.F.rows(); ++f) {
    s += 'f';
    for (int k = 0; k < 3; ++k) {
      s += ' ';
      appendInt(s, static_cast<long long>(mesh.F(f, k)) + 1);
    }
    s += '\n';
  }
  return writeBuffer(path, s, error);
}

template <typename T>
inline void appendRaw(std::string& s, const T& v) {
  s.append(reinterpret_cast<const char*>(&v), sizeof v);
}

bool hostIsLittleEndian() {
  const std::uint16_t one = 1;
  unsigned char b;
  std::memcpy(&b, &one, 1);
  return b == 1;
}

bool writePly(const std::string& path, const TriMesh& mesh, std::string& error) {
  std::string s;
  s += "ply\nformat ";
  s += hostIsLittleEndian() ? "binary_little_endian" : "binary_big_endian";
  s += " 1.0\ncomment virtual_tryon\nelement vertex ";
  appendInt(s, mesh.V.rows());
  s += "\nproperty double x\nproperty double y\nproperty double z\nelement face ";
  appendInt(s, mesh.F.rows());
  s += "\nproperty list uchar int vertex_indices\nend_header\n";
  s.reserve(s.size() + static_cast<std::size_t>(mesh.V.rows()) * 24 + static_cast<std::size_t>(mesh.F.rows()) * 13);
  for (Eigen::Index i = 0; i < mesh.V.rows(); ++i)
    for (int k = 0; k < 3; ++k) appendRaw(s, mesh.V(i, k));
  for (Eigen::Index f = 0; f < mesh.F.rows(); ++f) {
    appendRaw(s, static_cast<std::uint8_t>(3));
    for (int k = 0; k < 3; ++k) appendRaw(s, static_cast<std::int32_t>(mesh.F(f, k)));
  }
  return writeBuffer(path, s, error);
}

bool writeStl(const std::string& path, const TriMesh& mesh, std::string& error) {
  if (mesh.F.rows() == 0) {
    error = fail(path, "not written: an STL file cannot hold a mesh without faces");
    return false;
  }
  pcl::PolygonMesh pm;
  pcl::PCLPointCloud2& c = pm.cloud;
  const char* names[3] = {"x", "y", "z"};
  for (int k = 0; k < 3; ++k) {
    pcl::PCLPointField f;
    f.name = names[k];
    f.offset = static_cast<std::uint32_t>(4 * k);
    f.datatype = pcl::PCLPointField::FLOAT32;
    f.count = 1;
    c.fields.push_back(f);
  }
  c.height = 1;
  c.width = static_cast<std::uint32_t>(mesh.V.rows());
  c.point_step = 12;
  c.row_step = c.point_step * c.width;
  c.is_dense = true;
  c.is_bigendian = false;
  c.data.resize(static_cast<std::size_t>(c.row_step));
  for (Eigen::Index i = 0; i < mesh.V.rows(); ++i)
    for (int k = 0; k < 3; ++k) {
      const float v = static_cast<float>(mesh.V(i, k));
      std::memcpy(c.data.data() + 12 * i + 4 * k, &v, sizeof v);
    }
  pm.polygons.resize(static_cast<std::size_t>(mesh.F.rows()));
  for (Eigen::Index f = 0; f < mesh.F.rows(); ++f)
    pm.polygons[f].vertices.assign(mesh.F.row(f).data(), mesh.F.row(f).data() + 3);
  // Probe writability first: VTK only prints its complaint to stderr.
  {
    FilePtr probe(std::fopen(path.c_str(), "wb"));
    if (!probe) {
      error = fail(path, std::string("cannot open for writing: ") + std::strerror(errno));
      return false;
    }
  }
  if (pcl::io::savePolygonFileSTL(path, pm, /*binary_format=*/true) == 0) {
    error = fail(path, "PCL/VTK failed to write STL");
    return false;
  }
  return true;
}

}  // namespace

bool readMesh(const std::string& path, TriMesh& mesh, std::string& error, MeshReadInfo* info,
              const MeshLimits& limits) {
  const Format format = formatOf(path);
  if (format == Format::Unknown) {
    error = unknownFormatMessage(path);
    return false;
  }
  if (!checkReadable(path, error)) return false;
  MeshReadInfo localInfo;
  TriMesh result;
  bool ok = false;
  switch (format) {
    case Format::Obj: ok = readObj(path, result, error, localInfo, limits); break;
    case Format::Ply: ok = readPly(path, result, error, localInfo, limits); break;
    case Format::Stl: ok = readStl(path, result, error, localInfo, limits); break;
    case Format::Unknown: break;
  }
  if (!ok) return false;
  mesh = std::move(result);
  if (info) *info = localInfo;
  error.clear();
  return true;
}

bool writeMesh(const std::string& path, const TriMesh& mesh, std::string& error) {
  const Format format = formatOf(path);
  if (format == Format::Unknown) {
    error = unknownFormatMessage(path);
    return false;
  }
  if (!checkIndices(path, mesh, error)) return false;
  bool ok = false;
  switch (format) {
    case Format::Obj: ok = writeObj(path, mesh, error); break;
    case Format::Ply: ok = writePly(path, mesh, error); break;
    case Format::Stl: ok = writeStl(path, mesh, error); break;
    case Format::Unknown: break;
  }
  if (ok) error.clear();
  return ok;
}

}  // namespace virtual_tryon
