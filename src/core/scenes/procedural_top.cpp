#include "virtual_tryon/core/scenes/procedural_top.h"

#include "virtual_tryon/core/scenes/procedural_body.h"

#include <algorithm>
#include <cmath>
#include <functional>
#include <vector>

namespace virtual_tryon {
namespace {

// Largest connected piece of the faces of `mesh` kept by `keep(face)`, unused vertices dropped.
TriMesh largestPiece(const TriMesh& mesh, const std::function<bool(int)>& keep) {
  TriMesh cut;
  std::vector<int> faces;
  for (Eigen::Index f = 0; f < mesh.F.rows(); ++f)
    if (keep(static_cast<int>(f))) faces.push_back(static_cast<int>(f));
  cut.V = mesh.V;
  cut.F.resize(static_cast<Eigen::Index>(faces.size()), 3);
  for (std::size_t i = 0; i < faces.size(); ++i) cut.F.row(static_cast<Eigen::Index>(i)) = mesh.F.row(faces[i]);
  std::vector<int> label;
  const int n = connectedComponents(cut, label);
  std::vector<int> size(static_cast<std::size_t>(std::max(n, 1)), 0);
  for (Eigen::Index f = 0; f < cut.F.rows(); ++f) ++size[label[cut.F(f, 0)]];
  const int big = static_cast<int>(std::max_element(size.begin(), size.end()) - size.begin());
  std::vector<int> id(static_cast<std::size_t>(cut.V.rows()), -1);
  TriMesh out;
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

}  // namespace

ResolveScene makeProceduralTopScene(double bodyResolution, double garmentResolution) {
  ResolveScene s;
  ProceduralBodyParams bp;
  bp.resolution = bodyResolution;
  s.body = makeProceduralBody(bp);
  ProceduralBodyParams gp;
  gp.resolution = garmentResolution;
  TriMesh skin = makeProceduralBody(gp);
  const ProceduralBodyLandmarks lm = proceduralBodyLandmarks(bp);
  const MatrixX3d N = vertexNormals(skin);
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

}  // namespace virtual_tryon
