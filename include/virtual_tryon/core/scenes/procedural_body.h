// A procedural human-like body, made by the project (no external data): a smooth union
// (polynomial smooth-min, blend radius 2.5 cm at 1.70 m) of a lofted elliptical torso (crotch to
// the base of the neck: hips, waist, chest, sloping shoulders), capsules with tapering radii (neck,
// trapezius, upper arms, forearms, thighs, shins) and ellipsoids (head, deltoids, mitten hands,
// calves, feet), meshed from its implicit function by marching tetrahedra. Closed, consistently
// wound, outward, metres, +y up, faces +z, feet at y = 0, about 1.7 m tall. The arms hang 45 degrees
// below the horizontal (A-pose) with the hands far from the hips; the thighs leave a gap of a few
// centimetres below the crotch.
#pragma once

#include "virtual_tryon/core/geometry/mesh.h"

#include <functional>

namespace virtual_tryon {

struct ProceduralBodyParams {
  double height = 1.70;      // metres, feet to top of head; every length scales with height / 1.70
  double girth_scale = 1.0;  // scales torso and limb radii (and the hip/shoulder spacing), not the
                             // head, the feet or any length
  double resolution = 0.015; // grid cell size of the mesher, metres (0.015: ~32k vertices, ~65k
                             // triangles, ~0.1 s; keep it <= ~0.025 or the wrists and hands thin out)
};

// Signed implicit function of the body (negative inside, roughly the distance in metres near the
// surface; not an exact distance). The primitives for `params` are cached per thread, so calling it
// point by point is cheap.
double proceduralBodySdf(const Eigen::Vector3d& p, const ProceduralBodyParams& params = ProceduralBodyParams());

// The body mesh: meshImplicit(proceduralBodySdf) on the body's bounds plus two cells, at
// params.resolution. Closed 2-manifold (genus 0), outward, no degenerate faces, one connected
// component (should a fingertip come out as a separate sliver at a coarse resolution, only the
// largest piece is kept).
TriMesh makeProceduralBody(const ProceduralBodyParams& params = ProceduralBodyParams());

// Landmarks of the procedural body (for patterns and tests), metres, in the body frame (+y up,
// facing +z, feet at y = 0). "Left" is the body's own left, which is +x. Joint positions are the
// centres of the primitives (inside the body); the cross-section half-widths are measured on the
// actual implicit surface (zero crossings of proceduralBodySdf from the section centre).
struct ProceduralBodyLandmarks {
  double waist_y = 0, hip_y = 0, chest_y = 0, shoulder_y = 0, knee_y = 0;
  double crotch_y = 0;  // lowest point of the torso between the legs (on the surface, x = 0)
  double neck_y = 0;    // middle of the neck
  // Half-widths of the horizontal cross-sections at waist_y, hip_y, chest_y (x: half of the full
  // width including anything attached at that height, e.g. the thighs at the hips; z: half depth),
  // and the z of the section centre (front and back are at *_z +- *_radius_z).
  double waist_radius_x = 0, waist_radius_z = 0, waist_z = 0;
  double hip_radius_x = 0, hip_radius_z = 0, hip_z = 0;
  double chest_radius_x = 0, chest_radius_z = 0, chest_z = 0;
  Eigen::Vector3d left_shoulder = Eigen::Vector3d::Zero(), right_shoulder = Eigen::Vector3d::Zero();
  Eigen::Vector3d left_elbow = Eigen::Vector3d::Zero(), right_elbow = Eigen::Vector3d::Zero();
  Eigen::Vector3d left_wrist = Eigen::Vector3d::Zero(), right_wrist = Eigen::Vector3d::Zero();
  Eigen::Vector3d left_hand = Eigen::Vector3d::Zero(), right_hand = Eigen::Vector3d::Zero();  // palm centres
  Eigen::Vector3d left_hip_joint = Eigen::Vector3d::Zero(), right_hip_joint = Eigen::Vector3d::Zero();
  Eigen::Vector3d left_knee = Eigen::Vector3d::Zero(), right_knee = Eigen::Vector3d::Zero();
  Eigen::Vector3d left_ankle = Eigen::Vector3d::Zero(), right_ankle = Eigen::Vector3d::Zero();
  double arm_radius = 0;    // upper arm at the shoulder (tapers towards the elbow)
  double thigh_radius = 0;  // thigh at the hip joint (tapers towards the knee)
  double neck_radius = 0;
};
ProceduralBodyLandmarks proceduralBodyLandmarks(const ProceduralBodyParams& params = ProceduralBodyParams());

// Meshes {p : f(p) < 0} inside the box [lo, hi] on a grid of `cell` (nodes at lo + cell * (i, j, k),
// enough of them to cover hi): f is evaluated once per node (NaN counts as outside), every cube is
// split into the 6 tetrahedra around its main diagonal (the same split in every cube, so the pieces
// match across faces), and the surface vertices sit on the grid edges at the linear zero crossing
// (clamped to [0.001, 0.999] along the edge, so no triangle degenerates even where f = 0 at a node),
// shared by all tetrahedra around the edge. The result is the level set of the piecewise-linear
// interpolant: closed and manifold when the surface stays inside the box, outward (counter-clockwise
// seen from outside, signedVolume > 0), no unused vertices. Returns an empty mesh when nothing is
// inside (or the box is empty).
TriMesh meshImplicit(const std::function<double(const Eigen::Vector3d&)>& f, const Eigen::Vector3d& lo,
                     const Eigen::Vector3d& hi, double cell);

// Loop-free midpoint subdivision: every triangle into 4 (for "4x faces" benchmarks). The original
// vertices keep their indices and positions, followed by one new vertex per unique edge (in
// uniqueEdges order); face f becomes faces 4f..4f+3 with the same winding. Closed meshes stay closed
// and the shape (and volume) is unchanged.
TriMesh subdivideMidpoint(const TriMesh& mesh);

}  // namespace virtual_tryon
