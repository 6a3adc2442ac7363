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
// min_clearance from it (or as far as it was, if nearer). Otherwise it takes the largest clean part
// of that move, found by bisection; otherwise it stays where the resolver put it. The frame stays correct on its own
// (every move is checked against this frame's body); only the choice among clean positions follows
// the previous frame.
#pragma once

#include "virtual_tryon/core/body/body.h"

#include <cstddef>
#include <string>

namespace virtual_tryon {

struct CoherenceParams {
  double max_change = 0.003;   // m: the largest change of a vertex's correction from one frame to the next
  double min_clearance = 0;    // m: a moved vertex keeps at least this from the body
  int passes = 3;              // over the vertices still over max_change (a neighbour's move may free one)
  int bisections = 5;          // bisections for the largest clean part of a move that does not keep the frame clean
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
  double seconds = 0;
  std::string message;         // why nothing was done (sizes), else empty
};

// garment: the frame as resolved (#V by 3 positions move, faces do not); input: the frame's input
// (#V by 3); previousCorrection: the previous frame's resolved minus input (#V by 3). A size that
// does not match leaves the garment as it is (message says why).
CoherenceReport limitCorrectionChange(const Body& body, TriMesh& garment, const MatrixX3d& input,
                                      const MatrixX3d& previousCorrection,
                                      const CoherenceParams& params = CoherenceParams());

}  // namespace virtual_tryon
