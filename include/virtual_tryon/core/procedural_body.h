// A procedural human-like body, made by the project (no external data): a smooth union of
// capsules and ellipsoids (head, neck, torso, pelvis, arms in an A-pose, legs), meshed from its
// implicit function. Closed, consistently wound, outward, metres, +y up, faces +z, feet at y = 0,
// about 1.7 m tall.
#pragma once

#include "virtual_tryon/core/mesh.h"

#include <functional>

namespace virtual_tryon {

struct ProceduralBodyParams {
  double height = 1.70;      // metres, feet to top of head
  double girth_scale = 1.0;  // scales torso and limb radii
  double resolution = 0.015; // grid cell size of the mesher, metres
};

// Signed implicit function of the body (negative inside, roughly the distance in metres near the
// surface).
double proceduralBodySdf(const Eigen::Vector3d& p, const ProceduralBodyParams& params = ProceduralBodyParams());

// The body mesh.
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

// Meshes {p : f(p) < 0} inside the box [lo, hi] on a grid of `cell` (marching tetrahedra, shared
// vertices, outward winding). Closed when the surface stays inside the box.
TriMesh meshImplicit(const std::function<double(const Eigen::Vector3d&)>& f, const Eigen::Vector3d& lo,
                     const Eigen::Vector3d& hi, double cell);

// Loop-free midpoint subdivision: every triangle into 4 (for "4x faces" benchmarks).
TriMesh subdivideMidpoint(const TriMesh& mesh);

}  // namespace virtual_tryon
