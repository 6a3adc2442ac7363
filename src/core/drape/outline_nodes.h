// Internal to the core: the nodes that pattern_mesher.cpp puts on each panel's outline, and the
// seam pairs between them.
//
// Every seam places the same number of nodes on its two stretches, at the same arc-length
// fractions (a.from with b.from, a.to with b.to): the union of the fractions each side needs to
// follow its outline within `tolerance` (Douglas-Peucker), with points added evenly where a gap is
// longer than the spacing along the longer side. Node k of side a pairs with node k of side b, so a
// seam joins its stretches edge to edge. The rest of each outline (what no seam sews) gets nodes
// the same way on its own. Every outline vertex where a stretch starts or ends is a node, shared by
// the stretches that meet there.
#pragma once

#include "virtual_tryon/core/drape/pattern.h"

#include <string>
#include <vector>

namespace virtual_tryon {
namespace outline_nodes {

struct PanelLoop {
  std::vector<Eigen::Vector2d> uv;  // the nodes in counter-clockwise order round the outline
};

struct OutlineSampling {
  std::vector<PanelLoop> loops;  // per panel
  // Per seam, its node pairs as (panel-local loop index on a's panel, on b's panel).
  std::vector<std::vector<std::pair<int, int>>> seam_pairs;
};

// Samples every outline of a valid, normalised pattern (counter-clockwise outlines) at `spacing`,
// chords within `tolerance` (metres) of the outline. False with `error` when a seam cannot be
// placed (a stretch of zero length).
bool sampleOutlines(const Pattern& pattern, double spacing, double tolerance, OutlineSampling& out,
                    std::string& error);

}  // namespace outline_nodes
}  // namespace virtual_tryon
