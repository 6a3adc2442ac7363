// GarmentCode's pattern specification JSON (Korosteleva and Sorkine-Hornung 2023; the format of
// GarmentCode, GarmentCodeData and NeuralTailor), read into our Pattern.
#pragma once

#include "virtual_tryon/core/drape/pattern.h"
#include "virtual_tryon/core/io/garmentcode_edges.h"

#include <Eigen/Core>

#include <string>
#include <vector>

namespace virtual_tryon {

struct GarmentCodeReadParams {
  // Metres: curved edges are sampled at equal arc-length steps of at most this (the cloth's grid
  // spacing); straight edges keep their two ends.
  double spacing = 0.02;
  // A stitch whose two edges differ in length by more than this ratio (longer / shorter) gets a
  // warning with both lengths (ease and gathers of a few percent are normal: a sleeve cap is
  // usually 5-10% longer than its armhole).
  double warn_length_ratio = 1.25;
};

// What one stitch became.
struct GarmentCodeStitch {
  std::string panel_a, panel_b;
  int edge_a = -1, edge_b = -1;
  double length_a = 0, length_b = 0;  // metres, along the curves
  bool right_wrong = false;           // marked "right_wrong": start meets start (else start meets end)
  int segments = 0;                   // samples - 1 on each edge
  std::vector<int> seams;             // indices into Pattern::seams (a stitch over half of an
                                      // outline or more is split into seams shorter than that)
};

struct GarmentCodeReport {
  double units_in_meter = 100;
  std::vector<std::string> panel_names;  // in Pattern::panels order (the file's order)
  std::vector<GarmentCodeStitch> stitches;
  std::vector<std::string> warnings;
};

// Reads a pattern specification: properties.units_in_meter (default 100: centimetres) and
// curvature_coords ("relative", the default, or "absolute"); pattern.panels.NAME with vertices
// ([x, y] pairs), edges (endpoints [i, j], optional curvature: {type: quadratic | cubic | circle,
// params}, or the older bare [x, y] of a quadratic), translation and rotation (Euler degrees,
// R = Rz Ry Rx, GarmentCode's euler_xyz_to_R); pattern.stitches: pairs of {panel, edge}, an optional
// third item "right_wrong". panel_order, parameters, labels and anything else are ignored.
//
// The result, in GarmentCode's frame scaled to metres (its body stands on y = 0, y up, faces +z):
// - one PatternPanel per panel: its outline is the edge loop (each edge must start where the one
//   before it ends, the last ending where the first starts, every vertex used once), curved edges
//   sampled as GarmentCodeReadParams::spacing says; placement pose = translation * R, flat.
//   A clockwise panel (GarmentCode's back panels: their winding points their front side outward)
//   is mirrored, u -> -u, and its pose turned 180 degrees about its own y axis: the same points in
//   3D, now counter-clockwise with the same side out.
// - one seam per stitch (more when it must be split, see GarmentCodeStitch::seams): GarmentCode's
//   mesher joins the start of the first edge to the end of the second (the stitch sews the right
//   sides together), or start to start when marked "right_wrong"; both edges get the same number of
//   samples (the longer one's), so the nodes pair at equal arc-length fractions.
// Errors name the panel, edge and field ("panel 'left_ftorso' edge 3: curvature type 'spline' is
// not one of quadratic, cubic, circle"), then validatePattern runs with a length ratio of 2 (longer
// gathers are refused). On failure `pattern` is unchanged and false is returned; nothing is thrown.
// Limits (kMaxPattern*) are checked before outlines are sampled.
bool parseGarmentCodeJson(const std::string& text, const GarmentCodeReadParams& params, Pattern& pattern,
                          GarmentCodeReport& report, std::string& error);
// Same, from a file; messages start with the path.
bool readGarmentCodeJson(const std::string& path, const GarmentCodeReadParams& params, Pattern& pattern,
                         GarmentCodeReport& report, std::string& error);

// GarmentCode's rotation (rotation.py, euler_xyz_to_R): Euler angles in degrees, R = Rz Ry Rx.
Eigen::Matrix3d garmentCodeRotation(const Eigen::Vector3d& degrees);

// True when `text` (a file's start) is JSON (its first non-blank character is '{'), so a reader can
// pick the format by content as well as by extension.
bool looksLikeJson(const std::string& text);

}  // namespace virtual_tryon
