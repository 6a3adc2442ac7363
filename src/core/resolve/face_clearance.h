// Internal to the core: body vertices too near the middle of a garment face.
//
// A garment face wider than the body's faces can pass closer to a convex body than its corners: a
// 5 cm face over a shoulder blade sags 2-3 mm towards it while every corner keeps its clearance.
// Where the body has an uncertainty (a scan), that middle must clear the body too. Each body vertex
// y under garment face f, whose line y + t n (n: y's unit normal) meets f's plane inside f at
// |t| < c, is a "face clearance": the face's point there, sum_i w_i x_i, must satisfy
// n . sum_i w_i x_i >= n . y + c.
#pragma once

#include "virtual_tryon/core/body/body.h"
#include "virtual_tryon/core/geometry/mesh.h"

#include <array>
#include <vector>

namespace virtual_tryon {
namespace resolver_run {

struct FaceClearance {
  int face = -1;                        // garment face
  int body_vertex = -1;
  std::array<double, 3> weight{{0, 0, 0}};  // of the face's corners, summing to 1
  Eigen::Vector3d normal{0, 0, 0};      // the body vertex's unit normal
  double bound = 0;                     // normal . sum_i weight_i x_i must reach this
};

// Appends to `out` the face clearances of garment face f nearer than c (> 0), found among the
// corners of the body faces whose boxes overlap f's box grown by c.
void faceClearances(const Body& body, const TriMesh& garment, int f, double c, std::vector<FaceClearance>& out);

// The farthest any point of garment face f lies from its corner k (0..2): the longer of the two
// edges at that corner. A corner farther than this (plus a margin) from the body keeps the whole
// face that far off it.
double cornerReach(const TriMesh& garment, int f, int k);

// How far face clearance k is short of its bound (<= 0: met).
double shortfall(const FaceClearance& k, const TriMesh& garment);

}  // namespace resolver_run
}  // namespace virtual_tryon
