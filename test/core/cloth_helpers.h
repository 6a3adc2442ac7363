// Shared by the cloth suites (cloth, stiffness_spectrum): a cloth built in code, independent of
// the pattern mesher.
#pragma once

#include "virtual_tryon/core/drape/pattern.h"

#include <vector>

namespace virtual_tryon_test {

// A hand-made n x n grid of nodes with all three spring kinds (independent of the pattern mesher).
inline virtual_tryon::ClothMesh gridCloth(int n, double h) {
  using namespace virtual_tryon;
  ClothMesh c;
  c.spacing = h;
  c.X.resize(n * n, 3);
  c.UV.resize(n * n, 2);
  auto id = [n](int i, int j) { return j * n + i; };
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      c.X.row(id(i, j)) << i * h, 0.0, j * h;
      c.UV.row(id(i, j)) << i * h, j * h;
    }
  c.panel.assign(static_cast<std::size_t>(n * n), 0);
  auto add = [&](int a, int b, SpringType t) {
    c.springs.push_back({a, b, (c.UV.row(a) - c.UV.row(b)).norm(), t});
  };
  std::vector<Eigen::Vector3i> tris;
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      if (i + 1 < n) add(id(i, j), id(i + 1, j), SpringType::Structural);
      if (j + 1 < n) add(id(i, j), id(i, j + 1), SpringType::Structural);
      if (i + 1 < n && j + 1 < n) {
        add(id(i, j), id(i + 1, j + 1), SpringType::Shear);
        add(id(i + 1, j), id(i, j + 1), SpringType::Shear);
        c.quads.push_back({id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1)});
        tris.emplace_back(id(i, j), id(i + 1, j + 1), id(i + 1, j));
        tris.emplace_back(id(i, j), id(i, j + 1), id(i + 1, j + 1));
      }
      if (i + 2 < n) add(id(i, j), id(i + 2, j), SpringType::Flexion);
      if (j + 2 < n) add(id(i, j), id(i, j + 2), SpringType::Flexion);
    }
  c.F.resize(static_cast<Eigen::Index>(tris.size()), 3);
  for (std::size_t t = 0; t < tris.size(); ++t) c.F.row(static_cast<Eigen::Index>(t)) = tris[t].transpose();
  return c;
}

}  // namespace virtual_tryon_test
