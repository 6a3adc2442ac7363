// Temporal coherence of a garment resolved frame by frame (Sun et al. 2016's garment animation
// synthesis). Each frame is resolved on its own, and the resolver's discrete choices (which way a
// vertex leaves, how the relaxation spreads a push) can differ between neighbouring frames: a
// vertex's correction (resolved minus input) then jumps by a centimetre from one frame to the next
// although the input moves smoothly, and the garment flickers.
//
// limitCorrectionChange() takes a frame already resolved (clean) and, for each vertex whose
// correction changed by more than max_change since the previous frame, moves it towards its
// previous correction, to a change of max_change, where that keeps the frame clean: none of the
// vertex's faces or edges crosses the body, the vertex is not inside it, and it stays at least
// min_clearance from it (or as far as it was, if nearer); and the move keeps the shape: none of the
// vertex's edges is strained past max_strain (or past its strain as resolved, if more). Otherwise
// it takes the largest clean part of that move, found by bisection; otherwise it stays where the
// resolver put it. The frame stays correct on its own (every move is checked against this frame's
// body); only the choice among clean positions follows the previous frame.
//
// limitCorrectionChangeBackward() is the second pass over a recorded sequence (the whole cache at
// hand, tryon animate resolve), after every frame was resolved and limited forward: a jump the
// forward pass could not hold (the body lies between the vertex and its previous correction on the
// later frame) is spread over the frames before it, where nothing is in the way.
#pragma once

#include "virtual_tryon/core/body/body.h"
#include "virtual_tryon/core/resolve/penetration_resolver.h"

#include <cstddef>
#include <functional>
#include <string>
#include <vector>

namespace virtual_tryon {

struct CoherenceParams {
  double max_change = 0.003;   // m: the largest change of a vertex's correction from one frame to the next
  double min_clearance = 0;    // m: a moved vertex keeps at least this from the body
  int passes = 3;              // over the vertices still over max_change (a neighbour's move may free one)
  int bisections = 5;          // bisections for the largest clean part of a move that does not keep the frame clean
  // A move may not strain an edge at a moved vertex (|l / l0 - 1| against the frame's input) past
  // this, unless the resolver had already strained it more (then not past that): holding a vertex
  // near its previous correction must not tear its edges (0: no such check). The largest strain
  // the shape issue allows a resolve; at 0.2 (the polish's bound) the cold walk's female T-shirt
  // kept corrections that jumped 7.7 mm, at 0.3 none over 3 mm and the same largest strain.
  double max_strain = 0.3;
  // Rings of neighbours that move with a vertex, each the same fraction of its own way to its
  // previous correction (0: the vertex alone). The patch's shape then lies between the two
  // frames' resolved shapes, where a vertex moved alone would stand out of its neighbours.
  int rings = 0;
  // The rings of limitCorrectionChangeBackward's moves. A vertex that the body pushed out on a
  // later frame and that moves alone on the frames before stands out of its neighbours (on the
  // walk's male T-shirt, one such move took a frame's largest edge strain from 0.10 to 0.26; with
  // two rings 0.12, with one 0.16).
  int backward_rings = 2;
  // The garment's connectivity (penetration_resolver.h), when the caller has it; else built.
  std::shared_ptr<const GarmentConnectivity> connectivity;
};

struct CoherenceReport {
  std::size_t candidates = 0;  // vertices whose correction changed by more than max_change
  std::size_t limited = 0;     // of them, brought to a change of max_change
  std::size_t partly = 0;      // moved part of the way
  std::size_t held = 0;        // left where the resolver put them (no clean move)
  double change_before = 0;    // m: the largest change of a correction, as resolved
  double change_after = 0;     // m: the same after
  // Of the vertices still over max_change (partly + held), those the input forces: the previous
  // correction on this frame's input lies inside the body deeper than max_change, and a clean
  // position is outside it, so none is within max_change of the previous correction.
  std::size_t forced_by_input = 0;
  double change_after_unforced = 0;  // m: change_after over the vertices not forced
  std::size_t strain_refusals = 0;   // moves tried and refused because they would strain an edge past max_strain
  double seconds = 0;
  std::string message;         // why nothing was done (sizes), else empty
};

// garment: the frame as resolved (#V by 3 positions move, faces do not); input: the frame's input
// (#V by 3); previousCorrection: the previous frame's resolved minus input (#V by 3). A size that
// does not match leaves the garment as it is (message says why).
CoherenceReport limitCorrectionChange(const Body& body, TriMesh& garment, const MatrixX3d& input,
                                      const MatrixX3d& previousCorrection,
                                      const CoherenceParams& params = CoherenceParams());

struct BackwardCoherenceReport {
  std::vector<int> frames;                // the frames it moved, last first
  std::vector<CoherenceReport> reports;   // for each of them, limitCorrectionChange's against the next frame
  std::size_t candidates = 0;             // summed over those frames
  std::size_t limited = 0, partly = 0, held = 0;
  double change_before = 0;               // m: the largest change of a correction between consecutive frames, before
  double change_after = 0;                // m: the same after
  double seconds = 0;                     // bodyAt's included
  std::string message;                    // why nothing was done (sizes), else empty
};

// From the last frame but one back to the first, each frame whose corrections differ by more than
// max_change from the next frame's gets limitCorrectionChange() against that next correction: its
// vertices move towards where the next frame puts them, to a change of max_change, where that
// keeps this frame clean on its own body. A move may lift the change from the frame before over
// the limit; the pass mends that pair next, as it goes back, and never comes back to a pair it
// passed. Every frame stays correct on its own: only the choice among clean positions looks ahead.
//
// resolved: per frame the resolved garment's vertices (#V by 3 each; changed in place); inputs: per
// frame its input (as many, #V by 3); faces: the garment's (#F by 3); bodyAt(k): frame k's body,
// asked only for the frames that need a move, in falling order (valid until the next call);
// minClearance: per frame, the clearance a moved vertex keeps (CoherenceParams::min_clearance).
// The moves take params.backward_rings rings of neighbours along (params.rings is not used).
BackwardCoherenceReport limitCorrectionChangeBackward(std::vector<MatrixX3d>& resolved,
                                                      const std::vector<MatrixX3d>& inputs, const MatrixX3i& faces,
                                                      const std::function<const Body&(int)>& bodyAt,
                                                      const std::vector<double>& minClearance,
                                                      const CoherenceParams& params = CoherenceParams());

}  // namespace virtual_tryon
