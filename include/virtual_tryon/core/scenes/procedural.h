// Procedural meshes the project makes itself: bodies (closed, outward) and garments for tests and
// demos. All in metres; the y axis is up.
#pragma once

#include "virtual_tryon/core/geometry/mesh.h"

namespace virtual_tryon {

// Icosphere of `subdivisions` levels (20 * 4^s faces), closed and outward.
TriMesh makeSphere(double radius, const Eigen::Vector3d& center = Eigen::Vector3d::Zero(),
                   int subdivisions = 3);

// Capsule along y: a cylinder of `length` between two hemispheres, closed and outward.
TriMesh makeCapsule(double radius, double length, const Eigen::Vector3d& center = Eigen::Vector3d::Zero(),
                    int segments = 32, int rings = 16);

// Cylinder along y of `height`, closed with caps (outward) or open (a tube, `capped` false).
// `segments` around, `rings` along the height.
TriMesh makeCylinder(double radius, double height, const Eigen::Vector3d& center = Eigen::Vector3d::Zero(),
                     int segments = 32, int rings = 8, bool capped = true);

// Flat rectangular patch in the x-z plane at height y = center.y, nx by nz quads split into
// triangles, normal +y.
TriMesh makePatch(double width, double depth, int nx, int nz,
                  const Eigen::Vector3d& center = Eigen::Vector3d::Zero());

// Appends b to a (indices shifted).
TriMesh concatenate(const TriMesh& a, const TriMesh& b);

// Rotates the mesh about its centroid by `angle` radians about `axis`, then translates it.
TriMesh transformed(const TriMesh& mesh, const Eigen::Vector3d& axis, double angle,
                    const Eigen::Vector3d& translation);

}  // namespace virtual_tryon

namespace virtual_tryon {

// The built-in resolver scene: a capsule "torso" (radius 0.15 m, 0.6 m cylinder) and a wrinkled
// tube garment around it whose wrinkles dip up to 1.5 cm into the body.
struct ResolveScene {
  TriMesh body;
  TriMesh garment;
};
ResolveScene makeWrinkledTubeScene(int segments = 64, int rings = 40);

}  // namespace virtual_tryon
