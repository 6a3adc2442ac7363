#include "common.h"

#include "virtual_tryon/core/scenes/procedural_body.h"

#include <algorithm>
#include <cstdarg>
#include <iomanip>

namespace eval {

Csv::Csv(const std::string& path, const std::vector<std::string>& header)
    : path_(path), out_(path), columns_(header.size()) {
  for (std::size_t i = 0; i < header.size(); ++i) out_ << (i ? "," : "") << header[i];
  out_ << "\n";
  out_.flush();
}

void Csv::row(const std::vector<Cell>& cells) {
  if (cells.size() != columns_)
    std::fprintf(stderr, "evaluate: %s: row of %zu cells for %zu columns\n", path_.c_str(), cells.size(), columns_);
  for (std::size_t i = 0; i < cells.size(); ++i) out_ << (i ? "," : "") << cells[i].text();
  out_ << "\n";
  out_.flush();
}

namespace {
std::string jsonString(const std::string& s) {
  std::ostringstream o;
  o << '"';
  for (char c : s) {
    if (c == '"' || c == '\\') o << '\\' << c;
    else if (c == '\n') o << "\\n";
    else if (static_cast<unsigned char>(c) < 0x20) o << ' ';
    else o << c;
  }
  o << '"';
  return o.str();
}
}  // namespace

void Summary::set(const std::string& key, double v) {
  if (!std::isfinite(v)) {
    values_[key] = "null";
    return;
  }
  std::ostringstream o;
  o << std::setprecision(9) << v;
  values_[key] = o.str();
}
void Summary::set(const std::string& key, bool v) { values_[key] = v ? "true" : "false"; }
void Summary::set(const std::string& key, const std::string& v) { values_[key] = jsonString(v); }

bool Summary::write(const std::string& path) const {
  std::ofstream out(path);
  out << "{\n";
  for (const auto& [k, v] : values_) out << "  " << jsonString(k) << ": " << v << ",\n";
  out << "  \"notes\": [";
  for (std::size_t i = 0; i < notes_.size(); ++i) out << (i ? ",\n    " : "\n    ") << jsonString(notes_[i]);
  out << "\n  ]\n}\n";
  return static_cast<bool>(out);
}

Summary& summary() {
  static Summary s;
  return s;
}

void progress(const char* fmt, ...) {
  va_list ap;
  va_start(ap, fmt);
  std::fprintf(stderr, "evaluate: ");
  std::vfprintf(stderr, fmt, ap);
  std::fprintf(stderr, "\n");
  va_end(ap);
}

Timing timeRuns(int runs, const std::function<void()>& f) {
  std::vector<double> t;
  for (int r = 0; r < std::max(1, runs); ++r) {
    const double t0 = now();
    f();
    t.push_back(now() - t0);
  }
  std::sort(t.begin(), t.end());
  return {t[t.size() / 2], t.front(), t.back()};
}

vt::TriMesh largestPiece(const vt::TriMesh& mesh, const std::function<bool(int)>& keep) {
  vt::TriMesh cut;
  std::vector<int> faces;
  for (Eigen::Index f = 0; f < mesh.F.rows(); ++f)
    if (keep(static_cast<int>(f))) faces.push_back(static_cast<int>(f));
  cut.V = mesh.V;
  cut.F.resize(static_cast<Eigen::Index>(faces.size()), 3);
  for (std::size_t i = 0; i < faces.size(); ++i) cut.F.row(static_cast<Eigen::Index>(i)) = mesh.F.row(faces[i]);
  std::vector<int> label;
  const int n = vt::connectedComponents(cut, label);
  std::vector<int> size(static_cast<std::size_t>(std::max(n, 1)), 0);
  for (Eigen::Index f = 0; f < cut.F.rows(); ++f) ++size[label[cut.F(f, 0)]];
  const int big = static_cast<int>(std::max_element(size.begin(), size.end()) - size.begin());
  std::vector<int> id(static_cast<std::size_t>(cut.V.rows()), -1);
  vt::TriMesh out;
  std::vector<Eigen::RowVector3d> verts;
  std::vector<Eigen::RowVector3i> tris;
  for (Eigen::Index f = 0; f < cut.F.rows(); ++f) {
    if (label[cut.F(f, 0)] != big) continue;
    Eigen::RowVector3i t;
    for (int k = 0; k < 3; ++k) {
      int& i = id[cut.F(f, k)];
      if (i < 0) {
        i = static_cast<int>(verts.size());
        verts.push_back(cut.V.row(cut.F(f, k)));
      }
      t[k] = i;
    }
    tris.push_back(t);
  }
  out.V.resize(static_cast<Eigen::Index>(verts.size()), 3);
  for (std::size_t i = 0; i < verts.size(); ++i) out.V.row(static_cast<Eigen::Index>(i)) = verts[i];
  out.F.resize(static_cast<Eigen::Index>(tris.size()), 3);
  for (std::size_t i = 0; i < tris.size(); ++i) out.F.row(static_cast<Eigen::Index>(i)) = tris[i];
  return out;
}

BodyScene proceduralTopScene(double bodyResolution, double garmentResolution) {
  BodyScene s;
  vt::ProceduralBodyParams bp;
  bp.resolution = bodyResolution;
  s.body = vt::makeProceduralBody(bp);
  vt::ProceduralBodyParams gp;
  gp.resolution = garmentResolution;
  vt::TriMesh skin = vt::makeProceduralBody(gp);
  const vt::ProceduralBodyLandmarks lm = vt::proceduralBodyLandmarks(bp);
  const vt::MatrixX3d N = vt::vertexNormals(skin);
  for (Eigen::Index i = 0; i < skin.V.rows(); ++i) {
    const double y = skin.V(i, 1), a = std::atan2(skin.V(i, 0), skin.V(i, 2));
    const double wave = std::sin(5 * a) * std::cos(2 * M_PI * y / 0.12);
    skin.V.row(i) += (0.003 + 0.012 * wave) * N.row(i);
  }
  const double lo = lm.hip_y, hi = lm.waist_y + 0.6 * (lm.chest_y - lm.waist_y);
  s.garment = largestPiece(skin, [&](int f) {
    for (int k = 0; k < 3; ++k) {
      const double y = skin.V(skin.F(f, k), 1);
      if (y < lo || y > hi) return false;
    }
    return true;
  });
  return s;
}

}  // namespace eval
