// Bad and odd meshes shared by the malformed-input suites of each interface (conversions, CLI,
// services): each case is a body and a garment built from the wrinkled-tube scene, with what a
// resolve of them must give. Interface-specific cases (message layouts, file syntax) live in the
// suites themselves.
#pragma once

#include "virtual_tryon/core/geometry/mesh.h"
#include "virtual_tryon/core/scenes/procedural.h"

#include <limits>
#include <string>
#include <vector>

namespace vt_malformed {

namespace vt = virtual_tryon;

struct MeshCase {
  std::string name;
  vt::TriMesh body, garment;
  bool ok;              // false: refused (success = false, exit code 2)
  std::string message;  // substring of the error (ok = false) or of a warning (ok = true)
  bool warns = false;   // ok and a warning naming the problem is expected
};

// The good scene: the wrinkled tube round the capsule (resolves, converged).
inline vt::ResolveScene goodScene() { return vt::makeWrinkledTubeScene(32, 20); }

inline vt::TriMesh scaled(vt::TriMesh m, double s) {
  m.V *= s;
  return m;
}

inline vt::TriMesh moved(vt::TriMesh m, const Eigen::Vector3d& t) {
  m.V.rowwise() += t.transpose();
  return m;
}

inline vt::TriMesh withFace(vt::TriMesh m, int a, int b, int c) {
  m.F.conservativeResize(m.F.rows() + 1, 3);
  m.F.row(m.F.rows() - 1) << a, b, c;
  return m;
}

// Index of the body face whose centroid is highest (on the top cap, far from the garment).
inline Eigen::Index topFace(const vt::TriMesh& m) {
  Eigen::Index best = 0;
  double top = -1e300;
  for (Eigen::Index f = 0; f < m.F.rows(); ++f) {
    const double y = m.V(m.F(f, 0), 1) + m.V(m.F(f, 1), 1) + m.V(m.F(f, 2), 1);
    if (y > top) {
      top = y;
      best = f;
    }
  }
  return best;
}

inline std::vector<MeshCase> meshCases() {
  const vt::ResolveScene s = goodScene();
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();
  std::vector<MeshCase> cases;

  vt::TriMesh g = s.garment;
  g.V(5, 1) = nan;
  cases.push_back({"NaN garment coordinate", s.body, g, false, "NaN or Inf"});
  vt::TriMesh b = s.body;
  b.V(7, 0) = -inf;
  cases.push_back({"Inf body coordinate", b, s.garment, false, "NaN or Inf"});

  g = s.garment;
  g.F.resize(0, 3);
  cases.push_back({"garment with no faces", s.body, g, false, "no faces"});
  b = s.body;
  b.F.resize(0, 3);
  cases.push_back({"body with no faces", b, s.garment, false, "no faces"});

  // Every face of zero area: nothing to collide with or to move out (each face's corners on a line).
  g = s.garment;
  for (Eigen::Index v = 0; v < g.V.rows(); ++v) g.V.row(v) << 0.001 * static_cast<double>(v), 0, 0;
  cases.push_back({"garment whose every face has zero area", s.body, g, false, "zero area"});
  b = s.body;
  for (Eigen::Index v = 0; v < b.V.rows(); ++v) b.V.row(v) << 0, 0.001 * static_cast<double>(v), 0;
  cases.push_back({"body whose every face has zero area", b, s.garment, false, "zero area"});

  // Degenerate garment faces: a repeated index, and three collinear points.
  g = withFace(s.garment, 0, 0, 1);
  g.V.conservativeResize(g.V.rows() + 1, 3);
  g.V.row(g.V.rows() - 1) = 0.5 * (g.V.row(0) + g.V.row(1));
  g = withFace(g, 0, static_cast<int>(g.V.rows()) - 1, 1);
  cases.push_back({"degenerate garment faces", s.body, g, true, "2 degenerate faces", true});

  g = withFace(s.garment, s.garment.F(3, 0), s.garment.F(3, 1), s.garment.F(3, 2));
  cases.push_back({"duplicate garment face", s.body, g, true, "1 duplicate face", true});

  // Duplicate vertices: a copy of vertex F(0,0), which face 0 now uses (a crack in the garment).
  g = s.garment;
  g.V.conservativeResize(g.V.rows() + 1, 3);
  g.V.row(g.V.rows() - 1) = g.V.row(g.F(0, 0));
  g.F(0, 0) = static_cast<int>(g.V.rows()) - 1;
  cases.push_back({"duplicate garment vertices", s.body, g, true, "1 duplicate vertex", true});

  // Non-manifold body: a fin on an edge of the top face (a third face on that edge).
  b = s.body;
  {
    const Eigen::Index f = topFace(b);
    b.V.conservativeResize(b.V.rows() + 1, 3);
    b.V.row(b.V.rows() - 1) = 0.5 * (b.V.row(b.F(f, 0)) + b.V.row(b.F(f, 1))) + Eigen::RowVector3d(0, 0.1, 0);
    b = withFace(b, b.F(f, 0), b.F(f, 1), static_cast<int>(b.V.rows()) - 1);
  }
  cases.push_back({"non-manifold body", b, s.garment, true, "non-manifold", true});

  // Open body: the top face removed.
  b = s.body;
  {
    const Eigen::Index f = topFace(b);
    b.F.row(f) = b.F.row(b.F.rows() - 1);
    b.F.conservativeResize(b.F.rows() - 1, 3);
  }
  cases.push_back({"open body", b, s.garment, true, "body is open", true});

  b = s.body;
  b.F.col(1).swap(b.F.col(2));
  cases.push_back({"inverted body", b, s.garment, false, "inside out"});

  b = vt::concatenate(s.body, vt::makeSphere(0.1, Eigen::Vector3d(1.0, 0, 0), 2));
  cases.push_back({"body of two closed pieces", b, s.garment, true, "2 separate pieces", true});

  cases.push_back({"garment 1000 km from the body", s.body, moved(s.garment, Eigen::Vector3d(1e6, 0, 0)), true,
                   "m away from the body", true});
  // The capsule is 0.9 m tall; in millimetres of a 1.7 m person it is 1700 units tall.
  cases.push_back({"millimetres (a 1700 m body)", scaled(s.body, 1700 / 0.9), scaled(s.garment, 1700 / 0.9),
                   true, "millimetres", true});
  return cases;
}

}  // namespace vt_malformed
