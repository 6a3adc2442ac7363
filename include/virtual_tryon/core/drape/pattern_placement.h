// Placing a pattern made for one body on another. GarmentCode places its panels round its own
// average body: standing on y = 0, y up, facing +z, its torso centred on x = z = 0, 1.72 m tall.
// The rule below moves that placement onto the body being dressed (y up, facing +z, as every
// body here).
#pragma once

#include "virtual_tryon/core/body/body.h"
#include "virtual_tryon/core/drape/pattern.h"
#include "virtual_tryon/core/geometry/mesh.h"

#include <Eigen/Core>

#include <string>

namespace virtual_tryon {

constexpr double kGarmentCodeBodyHeight = 1.72;  // metres

// Seams that must close over the body. Panels placed for another body can put a seam's two sides
// where the straight line between them runs through this body (a shoulder seam level with
// shoulders that sit higher than the pattern's body's): the seam pull then presses both sides onto
// the body and they slide down instead of meeting over it. seamLift finds the least lift of the
// whole pattern (0, step, 2 step, .. max_lift) with the fewest blocked seam lines: lines between
// the two sides of each seam at `fractions` evenly spread arc-length fractions of both stretches
// (lines shorter than min_length left out: they weld where they are), blocked when a point every
// `step` along the line is inside the body or nearer to it than `clearance` (a line grazing the
// body stalls as surely as one through it), then `margin_steps` steps more (a lift that only just
// clears a shoulder still left GarmentCode's shirt caught on body_hm08's: 1 cm stalled two seams,
// 2 cm sewed them all). Needs a closed body (pointInsideBody); an open one gives lift 0.
struct SeamLiftParams {
  double step = 0.01;        // metres
  double max_lift = 0.15;    // metres
  int fractions = 9;
  double clearance = 0.01;   // metres
  double min_length = 0.03;  // metres
  int margin_steps = 1;
};

struct SeamLift {
  double lift = 0;                              // metres, along +y
  int lines = 0;                                // seam lines tested
  int blocked_before = 0, blocked_after = 0;    // of them, at lift 0 and at `lift` (margin included)
};


struct BodyPlacementParams {
  // Also scale the panels' positions (not their outlines: the garment keeps its size) about the
  // floor point under the torso centre by the body's height / source_height.
  bool scale_to_height = false;
  double source_height = kGarmentCodeBodyHeight;
  double hip_height = 0.53;        // where the torso centre is taken, as a fraction of the height
  double slice_half_height = 0.02; // metres: the body's vertices this near that height form the slice
  double torso_half_width = 0.10;  // metres: slice vertices this near the body's x centre give its z
  bool lift_seams = true;          // placePatternOnBody: then lift by seamLift
  SeamLiftParams lift;
};

// Where the pattern's frame goes: a panel pose's translation t becomes scale * t + offset.
struct BodyPlacement {
  Eigen::Vector3d offset = Eigen::Vector3d::Zero();
  double scale = 1;
  Eigen::Vector3d torso_centre = Eigen::Vector3d::Zero();  // on the body, at hip height
  double body_height = 0, floor = 0;                       // metres, y of the lowest point
  SeamLift lift;                                           // placePatternOnBody's lift
  std::string rule;                                        // one line, for reports
};

// The rule: the floor (y = 0) goes to the body's lowest point; x and z go to the centre of the body's
// cross-section at hip height (x: the middle of the body's whole x extent, which arms held
// symmetrically do not move; z: the middle of the slice's z extent over vertices within
// torso_half_width of that x, so that hands and arms beside the hips do not count); with
// scale_to_height, positions are scaled by body height / source height about that floor point.
// bodyV: #V by 3, V > 0, y up.
BodyPlacement placementOnBody(const MatrixX3d& bodyV, const BodyPlacementParams& params = BodyPlacementParams());

// Applies it: every panel pose's translation t -> scale * t + offset (rotations and outlines kept).
void applyPlacement(const BodyPlacement& placement, Pattern& pattern);

SeamLift seamLift(const Body& body, const Pattern& pattern, const SeamLiftParams& params = SeamLiftParams());

// The whole rule on `pattern`: placementOnBody, applyPlacement, then (params.lift_seams) the seam
// lift added to offset.y and applied too. The returned placement's offset includes the lift.
BodyPlacement placePatternOnBody(const Body& body, Pattern& pattern,
                                 const BodyPlacementParams& params = BodyPlacementParams());

}  // namespace virtual_tryon
