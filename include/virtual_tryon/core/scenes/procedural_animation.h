// A short animation that the project makes itself, for tests and the animation bag: the procedural
// body skinned to two bones (below the waist fixed, above it a torso bone turning about a
// front-to-back axis through the waist, the two blended linearly over 20 cm round the waist) and
// swaying from side to side; the demo's wrinkled waist tube, which penetrates the body in its
// folds, skinned to the same bones, as a garment animation synthesis gives a garment.
#pragma once

#include "virtual_tryon/core/geometry/mesh.h"

#include <vector>

namespace virtual_tryon {

struct ProceduralAnimationParams {
  int frames = 12;           // >= 1
  double rate = 30;          // frames per second
  double amplitude = 0.14;   // rad: the torso's largest side bend (about 8 degrees)
  // s: one sway, left and back and right and back; a clip shorter than a quarter of it (15 frames at
  // 30 Hz) bends one way only, so that no two of its frames are the same pose (a body frame equal
  // to the one before is nothing new to the node).
  double period = 2.0;
  double blend = 0.10;       // m: the bones' weights blend from waist - blend to waist + blend
};

struct ProceduralAnimation {
  TriMesh body, garment;                  // the rest meshes (frame 0 is the rest pose)
  std::vector<MatrixX3d> body_frames;     // per frame: #V by 3, the body's vertex order
  std::vector<MatrixX3d> garment_frames;  // per frame: #V by 3, the garment's vertex order
  double rate = 30;
};

// The torso bone's angle at frame f: amplitude * sin(2 pi f / (rate * period)).
double proceduralSwayAngle(const ProceduralAnimationParams& params, int frame);

// Vertices V (#V by 3) posed at frame f by the two-bone skinning above (the procedural body's
// landmarks give the waist).
MatrixX3d poseProcedural(const MatrixX3d& V, const ProceduralAnimationParams& params, int frame);

ProceduralAnimation makeProceduralAnimation(const ProceduralAnimationParams& params = ProceduralAnimationParams());

}  // namespace virtual_tryon
