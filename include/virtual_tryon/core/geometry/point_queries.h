// Point queries against a body: nearest surface point and inside/outside.
#pragma once

#include "virtual_tryon/core/body/body.h"

#include <vector>

namespace virtual_tryon {

struct ClosestPoint {
  Eigen::Vector3d point{0, 0, 0};  // nearest point on the body surface
  int face = -1;                   // face it lies on
  double distance = 0;             // unsigned, metres
};

// Nearest point of triangle (a, b, c) to p.
Eigen::Vector3d closestPointOnTriangle(const Eigen::Vector3d& p, const Eigen::Vector3d& a,
                                       const Eigen::Vector3d& b, const Eigen::Vector3d& c);

// Nearest point on the body surface to p (through the body's BVH).
ClosestPoint closestPointOnBody(const Body& body, const Eigen::Vector3d& p);

// Ray-parity inside test for a closed body: casts three rays in fixed generic directions and takes
// the majority, so a ray grazing an edge or vertex cannot decide alone. Meaningless for an open
// body (returns false when !body.closed()).
bool pointInsideBody(const Body& body, const Eigen::Vector3d& p);

// For each row of P (#P by 3), the index of its nearest row of V (#V by 3), through PCL's k-d tree
// (single precision: a near tie may go either way); -1 when V is empty. For a binding to vertices that need no faces or tree,
// e.g. the body of a frame already left behind.
std::vector<int> nearestVertices(const MatrixX3d& V, const MatrixX3d& P);

}  // namespace virtual_tryon
