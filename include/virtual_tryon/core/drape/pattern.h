// Garment patterns (Vassilev et al. 2001, sec. 1): panels cut from cloth, placed around the body,
// and seams that sew stretches of panel outlines together. Meshing turns the panels into regular
// grids of mass points (the paper's rectangular topology) inside, with a band of triangles that
// follows the outline, and triangles for output.
#pragma once

#include "virtual_tryon/core/geometry/mesh.h"

#include <Eigen/Geometry>

#include <array>
#include <string>
#include <vector>

namespace virtual_tryon {

using MatrixX2d = Eigen::Matrix<double, Eigen::Dynamic, 2, Eigen::RowMajor>;

// Where a panel starts around the body.
// Flat: panel point (u, v) goes to pose * (u, v, 0): the panel lies in the pose's x-y plane and
// faces the pose's +z.
// Wrapped on a cylinder of `wrap_radius` whose axis is the pose's y axis through the pose's origin:
// (u, v) goes to pose * (r sin(u / r), v, r cos(u / r)), so u = 0 lies on the pose's +z side and
// the panel curls round the axis (sleeves, trouser legs, skirts round the body).
struct PanelPlacement {
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  double wrap_radius = 0;  // 0: flat
  Eigen::Vector3d place(const Eigen::Vector2d& uv) const;
};

struct PatternPanel {
  std::string name;
  MatrixX2d outline;  // #P by 2, a simple polygon in metres, counter-clockwise
  PanelPlacement placement;
};

// A stretch of a panel's outline: the walk along the outline from vertex `from` to vertex `to`,
// going the way round that passes fewer outline edges (wrapping past the last vertex when that is
// the shorter way). So on a 4-point outline {1, 2} is edge 1-2 walked from 1 to 2, {0, 3} is edge
// 3-0 walked from 0 to 3, and swapping from and to walks the same edges the other way. The walk
// is a property of the outline's geometry, not of its index order, so reversing an outline
// (normalizePattern) keeps every stretch on the same points in the same direction.
// from == to is not allowed, and neither is a stretch exactly half-way round an outline with an
// even number of points (either way would do: split such a seam in two); a stretch over more than
// half of an outline is written as two seams.
struct OutlineStretch {
  int panel = -1;
  int from = 0;
  int to = 0;
};

// A seam sews stretch a to stretch b; the walk along a pairs with the walk along b in order, so
// the direction of each stretch matters (a.from meets b.from, a.to meets b.to). Both stretches may
// lie on the same panel (a tube from one panel, a dart).
struct PatternSeam {
  OutlineStretch a, b;
  // Sewing order: a seam pulls only once every seam of a lower stage is welded (0 first). Lets a
  // garment close its body before sleeves are set into the armholes.
  int stage = 0;
};

struct Pattern {
  std::string name;
  std::vector<PatternPanel> panels;
  std::vector<PatternSeam> seams;
};

// Checks a pattern: at least one panel, outlines of >= 3 finite points, no two outline points in
// a row equal, not self-intersecting (no two non-adjacent edges meet, touching included), non-zero
// area (clockwise outlines are reversed by normalizePattern, not refused), finite placements with
// a proper rotation and a finite wrap radius >= 0, seams naming existing panels and outline
// vertices with from != to and not exactly half-way round, and seam stretches whose lengths differ
// by at most `maxLengthRatio` (longer / shorter). Returns "" when usable, else the first problem:
// "panel 'front' (index 0): ..." or "seam 2: ...".
// Also refused, before anything else is looked at (the self-intersection test is quadratic in the
// outline size): more than kMaxPatternPanels panels, an outline of more than kMaxOutlinePoints
// points, more than kMaxPatternOutlinePoints outline points in all, more than kMaxPatternSeams
// seams. Real garments have a few panels of a few dozen points.
std::string validatePattern(const Pattern& pattern, double maxLengthRatio = 1.5);

constexpr std::size_t kMaxPatternPanels = 256;
constexpr std::size_t kMaxOutlinePoints = 2048;
constexpr std::size_t kMaxPatternOutlinePoints = 16384;
constexpr std::size_t kMaxPatternSeams = 4096;

// Makes every outline counter-clockwise: a clockwise outline of n points is reversed (point i
// becomes point n-1-i) and every stretch on it is renumbered the same way (from -> n-1-from,
// to -> n-1-to), which keeps it on the same points walked in the same direction, so every seam
// still sews the same points together.
void normalizePattern(Pattern& pattern);

// Length of a stretch along its panel's outline (metres); 0 when the stretch is not valid.
double stretchLength(const Pattern& pattern, const OutlineStretch& s);

// The outline vertex indices a stretch walks through, `from` first and `to` last; empty when the
// stretch does not name an existing panel and two distinct vertices of its outline.
std::vector<int> stretchVertices(const Pattern& pattern, const OutlineStretch& s);

// The openings a sewn pattern must have: the loops of outline that no seam sews, once every
// seam has joined its stretches' ends (a.from to b.from, a.to to b.to). A tube of one panel
// sewn side to side has 2, a T-shirt (neck, waist, two sleeve ends) 4. For a valid pattern.
int patternOpenings(const Pattern& pattern);

// Signed area of an outline (shoelace): > 0 when counter-clockwise.
double outlineSignedArea(const MatrixX2d& outline);

enum class SpringType { Structural = 0, Shear = 1, Flexion = 2 };

struct Spring {
  int a = -1, b = -1;
  double rest = 0;  // rest length from the flat panel, metres
  SpringType type = SpringType::Structural;
};

// A pair of mass points that a seam pulls together.
struct SeamPair {
  int a = -1, b = -1;
  int seam = -1;  // index into pattern.seams
};

// All panels meshed into one cloth.
struct ClothMesh {
  MatrixX3d X;                           // #N by 3 placed start positions
  MatrixX2d UV;                          // #N by 2 positions in the flat panel
  std::vector<int> panel;                // #N panel index per node
  MatrixX3i F;                           // #T by 3 triangles: two per grid quad, then the band's
  std::vector<std::array<int, 4>> quads; // grid quads (corners in order round the quad)
  std::vector<Spring> springs;           // structural, shear and flexion
  std::vector<SeamPair> seam_pairs;
  std::vector<int> seam_stage;           // per pattern seam, its PatternSeam::stage
  double spacing = 0;                    // grid spacing used, metres
};

// Meshes every panel into the paper's regular grid of `spacing` (metres) inside, and a band of
// triangles along its outline whose outer edge is a loop of nodes on the outline itself; seams pair
// those outline nodes one to one. Returns false with `error` when the pattern is invalid, over the
// limits, or a band cannot be triangulated.
//
// Details. The pattern is normalised first (normalizePattern). Per panel the grid has
// floor(width / spacing) + 1 by floor(height / spacing) + 1 nodes centred on the outline's bounding
// box; a grid node is kept when it lies inside the outline at least half a spacing from it. Two
// grid neighbours are linked only when the segment between them stays inside the outline (a notch
// narrower than the spacing is not bridged); a quad needs its four corners kept and its four sides
// linked; quads that would touch others at a corner only are dropped (one of each pair); kept nodes
// in no quad are dropped. Quads are (i,j), (i+1,j), (i+1,j+1), (i,j+1), counter-clockwise in uv,
// two triangles each (c0,c1,c2), (c0,c2,c3). Grid springs: structural i/j +-1 (linked), shear both
// diagonals, flexion i/j +-2 with the middle node kept and both halves linked.
// Outline nodes (outline_nodes.h): every seam places as many nodes on its two stretches, at the
// same arc-length fractions (a.from with b.from, a.to with b.to): the fractions each side needs
// for its chords to stay within 0.5% of the spacing of its outline (Douglas-Peucker), merged where
// closer than 0.3 spacing, with points added evenly into gaps longer than the spacing along the
// longer side. The rest of the outline gets nodes the same way on its own; stretch ends are shared
// nodes. The band between the outline loop and the grid's edge is triangulated by ear clipping
// over bridged holes and made constrained-Delaunay by edge flips (boundary_band.h); band springs:
// structural along every band edge that is not a grid spring, flexion across every band edge whose
// two triangles make a convex quad. Rest lengths from UV; no spring twice.
// Nodes: panel by panel, its grid nodes (row by row) and then its outline nodes (counter-clockwise
// from the panel's first stretch end, or outline point 0). Triangles: the
// quads' first, then the band's, all counter-clockwise in uv (normals along the pose's +z, outward
// for a wrap). Seam pairs: node k of side a with node k of side b (pairs of one node dropped).
// Size: the grids of all panels together (before clipping to the outlines) may hold at most
// 4 x limits.max_vertices nodes, and the cloth at most limits.max_vertices nodes; both are checked
// before the grids are allocated (the first) or the cloth is (the second).
bool meshPattern(const Pattern& pattern, double spacing, ClothMesh& cloth, std::string& error,
                 const MeshLimits& limits = MeshLimits());

}  // namespace virtual_tryon
