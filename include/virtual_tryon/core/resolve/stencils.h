// Penetration stencils (Sun et al. 2016, sec. 2): one scalar constraint D(x) >= d per edge-face
// crossing, linear in the garment positions x, with gradient Dx.
//
// Garment edge crossing a body face f (normal n, outward):
//   the end-point behind f is illegal, x0; D = n . (x0 - p), p the crossing point (eq. 1).
//   Gradient: n on x0. Several edges of x0 crossing the same face give one stencil.
//
// Body edge e crossing a garment face (x1, x2, x3) at the point p with barycentric weights w:
//   the garment point c = w1 x1 + w2 x2 + w3 x3 (= p now) must clear the body surface along the
//   body's outward direction at e, n_e (the unit mean of the normals of the faces at e):
//   D = n_e . (c - p), so D = 0 now, and D >= d asks the face to pass the ridge by d.
//   Gradient: w_i n_e on x_i, i = 1..3. Only the garment moves; the body edge is fixed.
#pragma once

#include "virtual_tryon/core/body/body.h"
#include "virtual_tryon/core/resolve/intersections.h"

#include <array>
#include <vector>

namespace virtual_tryon {

struct Stencil {
  int count = 1;                        // garment vertices involved: 1 (vertex-face) or 3 (face)
  std::array<int, 3> vertex{{-1, -1, -1}};
  std::array<double, 3> weight{{1, 0, 0}};
  Eigen::Vector3d normal{0, 0, 1};      // unit direction of the gradient
  double D = 0;                         // constraint value now (negative: penetrating)
};

// One stencil per crossing (merged where identical). `illegal` receives the garment vertices
// found behind a body face this round (sorted, unique).
std::vector<Stencil> buildStencils(const Body& body, const TriMesh& garment,
                                   const GarmentTopology& topo, const CrossingSet& crossings,
                                   std::vector<int>* illegal = nullptr);

}  // namespace virtual_tryon
