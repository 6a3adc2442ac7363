#include "virtual_tryon/core/scenes/procedural.h"

#include <Eigen/Geometry>

#include <cmath>
#include <map>
#include <vector>

namespace virtual_tryon {
namespace {

TriMesh fromVectors(const std::vector<Eigen::Vector3d>& v, const std::vector<Eigen::Vector3i>& f) {
  TriMesh m;
  m.V.resize(static_cast<Eigen::Index>(v.size()), 3);
  m.F.resize(static_cast<Eigen::Index>(f.size()), 3);
  for (std::size_t i = 0; i < v.size(); ++i) m.V.row(static_cast<Eigen::Index>(i)) = v[i].transpose();
  for (std::size_t i = 0; i < f.size(); ++i) m.F.row(static_cast<Eigen::Index>(i)) = f[i].transpose();
  return m;
}

// A surface of revolution about y: profile (r(t), y(t)) for rows t = 0..rows, each row a ring of
// `segments` vertices; r == 0 rows collapse into one pole vertex. Faces wind outward when the
// profile runs from the bottom (low y) to the top.
TriMesh revolve(const std::vector<std::pair<double, double>>& profile, int segments,
                const Eigen::Vector3d& center) {
  std::vector<Eigen::Vector3d> v;
  std::vector<Eigen::Vector3i> f;
  std::vector<std::vector<int>> ring(profile.size());
  const double pi = std::acos(-1.0);
  for (std::size_t r = 0; r < profile.size(); ++r) {
    const auto [rad, y] = profile[r];
    if (rad == 0) {
      ring[r].assign(static_cast<std::size_t>(segments), static_cast<int>(v.size()));
      v.push_back(center + Eigen::Vector3d(0, y, 0));
      continue;
    }
    for (int s = 0; s < segments; ++s) {
      const double a = 2 * pi * s / segments;
      ring[r].push_back(static_cast<int>(v.size()));
      v.push_back(center + Eigen::Vector3d(rad * std::cos(a), y, -rad * std::sin(a)));
    }
  }
  for (std::size_t r = 0; r + 1 < profile.size(); ++r)
    for (int s = 0; s < segments; ++s) {
      const int s1 = (s + 1) % segments;
      const int a = ring[r][s], b = ring[r][s1], c = ring[r + 1][s1], d = ring[r + 1][s];
      if (a != b) f.emplace_back(a, b, c);
      if (c != d) f.emplace_back(a, c, d);
    }
  return fromVectors(v, f);
}

}  // namespace

TriMesh makeSphere(double radius, const Eigen::Vector3d& center, int subdivisions) {
  const double t = (1.0 + std::sqrt(5.0)) / 2.0;
  std::vector<Eigen::Vector3d> v = {{-1, t, 0}, {1, t, 0},  {-1, -t, 0}, {1, -t, 0},
                                    {0, -1, t}, {0, 1, t},  {0, -1, -t}, {0, 1, -t},
                                    {t, 0, -1}, {t, 0, 1},  {-t, 0, -1}, {-t, 0, 1}};
  for (auto& p : v) p.normalize();
  std::vector<Eigen::Vector3i> f = {{0, 11, 5}, {0, 5, 1},  {0, 1, 7},   {0, 7, 10}, {0, 10, 11},
                                    {1, 5, 9},  {5, 11, 4}, {11, 10, 2}, {10, 7, 6}, {7, 1, 8},
                                    {3, 9, 4},  {3, 4, 2},  {3, 2, 6},   {3, 6, 8},  {3, 8, 9},
                                    {4, 9, 5},  {2, 4, 11}, {6, 2, 10},  {8, 6, 7},  {9, 8, 1}};
  for (int s = 0; s < subdivisions; ++s) {
    std::map<std::pair<int, int>, int> mid;
    auto midpoint = [&](int a, int b) {
      const auto key = std::make_pair(std::min(a, b), std::max(a, b));
      auto it = mid.find(key);
      if (it != mid.end()) return it->second;
      v.push_back((v[a] + v[b]).normalized());
      return mid[key] = static_cast<int>(v.size()) - 1;
    };
    std::vector<Eigen::Vector3i> g;
    for (const auto& tri : f) {
      const int a = midpoint(tri[0], tri[1]), b = midpoint(tri[1], tri[2]), c = midpoint(tri[2], tri[0]);
      g.emplace_back(tri[0], a, c);
      g.emplace_back(tri[1], b, a);
      g.emplace_back(tri[2], c, b);
      g.emplace_back(a, b, c);
    }
    f.swap(g);
  }
  for (auto& p : v) p = center + radius * p;
  return fromVectors(v, f);
}

TriMesh makeCapsule(double radius, double length, const Eigen::Vector3d& center, int segments,
                    int rings) {
  const double pi = std::acos(-1.0);
  std::vector<std::pair<double, double>> prof;
  const int half = std::max(rings / 2, 2);
  for (int i = 0; i <= half; ++i) {  // bottom hemisphere, pole first
    const double a = -pi / 2 + (pi / 2) * i / half;
    prof.push_back({i == 0 ? 0.0 : radius * std::cos(a), -length / 2 + radius * std::sin(a)});
  }
  for (int i = 0; i <= half; ++i) {  // top hemisphere
    const double a = (pi / 2) * i / half;
    prof.push_back({i == half ? 0.0 : radius * std::cos(a), length / 2 + radius * std::sin(a)});
  }
  return revolve(prof, segments, center);
}

TriMesh makeCylinder(double radius, double height, const Eigen::Vector3d& center, int segments,
                     int rings, bool capped) {
  std::vector<std::pair<double, double>> prof;
  if (capped) prof.push_back({0.0, -height / 2});
  for (int i = 0; i <= rings; ++i) prof.push_back({radius, -height / 2 + height * i / rings});
  if (capped) prof.push_back({0.0, height / 2});
  return revolve(prof, segments, center);
}

TriMesh makePatch(double width, double depth, int nx, int nz, const Eigen::Vector3d& center) {
  std::vector<Eigen::Vector3d> v;
  std::vector<Eigen::Vector3i> f;
  for (int j = 0; j <= nz; ++j)
    for (int i = 0; i <= nx; ++i)
      v.push_back(center + Eigen::Vector3d(-width / 2 + width * i / nx, 0, depth / 2 - depth * j / nz));
  auto id = [&](int i, int j) { return j * (nx + 1) + i; };
  for (int j = 0; j < nz; ++j)
    for (int i = 0; i < nx; ++i) {
      f.emplace_back(id(i, j), id(i + 1, j), id(i + 1, j + 1));
      f.emplace_back(id(i, j), id(i + 1, j + 1), id(i, j + 1));
    }
  return fromVectors(v, f);
}

TriMesh concatenate(const TriMesh& a, const TriMesh& b) {
  TriMesh m;
  m.V.resize(a.V.rows() + b.V.rows(), 3);
  m.V << a.V, b.V;
  m.F.resize(a.F.rows() + b.F.rows(), 3);
  m.F << a.F, (b.F.array() + static_cast<int>(a.V.rows())).matrix();
  return m;
}

TriMesh transformed(const TriMesh& mesh, const Eigen::Vector3d& axis, double angle,
                    const Eigen::Vector3d& translation) {
  TriMesh m = mesh;
  const Eigen::RowVector3d c = mesh.V.colwise().mean();
  const Eigen::Matrix3d R = Eigen::AngleAxisd(angle, axis.normalized()).toRotationMatrix();
  for (Eigen::Index i = 0; i < m.V.rows(); ++i)
    m.V.row(i) = ((R * (mesh.V.row(i) - c).transpose()).transpose() + c + translation.transpose());
  return m;
}

}  // namespace virtual_tryon

namespace virtual_tryon {

ResolveScene makeWrinkledTubeScene(int segments, int rings) {
  ResolveScene s;
  s.body = makeCapsule(0.15, 0.6, Eigen::Vector3d::Zero(), 48, 24);
  s.garment = makeCylinder(1.0, 0.5, Eigen::Vector3d::Zero(), segments, rings, false);
  const double pi = std::acos(-1.0);
  for (Eigen::Index i = 0; i < s.garment.V.rows(); ++i) {
    const double x = s.garment.V(i, 0), y = s.garment.V(i, 1), z = s.garment.V(i, 2);
    const double a = std::atan2(-z, x);
    const double r = 0.155 + 0.02 * std::sin(3 * a) * std::cos(2 * pi * y / 0.25);
    s.garment.V(i, 0) = r * std::cos(a);
    s.garment.V(i, 2) = -r * std::sin(a);
  }
  return s;
}

}  // namespace virtual_tryon
