// A recorded motion's body frames, each made ready one frame ahead of the worn garment: while the
// cloth steps through frame k (WornGarment::follow), a second thread refits the body to frame k + 1
// (Body's frame constructor: same faces, trees refitted) and renders its maps (WornMapRenderer).
// On two cores this takes the body's refit and the maps off the cloth's path; each frame's result
// is the same as stepping the frames one after the other (the renderer is the garment's own, copied,
// and renders the frames in order).
//
//   FramesAhead ahead(std::move(body0), frames, worn.mapRenderer(), 1.0 / 30);
//   while (!ahead.done()) {
//     FramesAhead::Frame f = ahead.next();
//     worn.follow(*f.body, std::move(f.maps));
//   }
#pragma once

#include "virtual_tryon/core/body/body.h"
#include "virtual_tryon/core/drape/worn_maps.h"

#include <future>
#include <memory>
#include <vector>

namespace virtual_tryon {

class FramesAhead {
 public:
  // `first`: the body on frames[0] (taken over; the caller may go on reading it, not changing it,
  // until its first next(): frame 1 is made from a copy, so that the garment can be draped on the
  // first frame while frame 1 is made ready, WornGarment::dress's mapsReady). frames (kept by the
  // caller while this lives): the body's vertices per frame (each #V by 3, as many as first has),
  // `seconds` apart (> 0). ahead: each frame is prepared on a second thread while the caller works
  // on the one before; false: next() prepares it on the calling thread (the same results, one
  // after the other).
  FramesAhead(std::unique_ptr<Body> first, const std::vector<MatrixX3d>& frames, WornMapRenderer renderer,
              double seconds, bool ahead = true);
  ~FramesAhead();  // waits for a frame in preparation
  FramesAhead(const FramesAhead&) = delete;
  FramesAhead& operator=(const FramesAhead&) = delete;

  struct Frame {
    int index = 0;                // into frames (1, 2, ...)
    const Body* body = nullptr;   // valid until the next call to next()
    WornFrameMaps maps;           // for WornGarment::follow(*body, maps)
    double seconds_body = 0;      // wall time of the body's refit
    double seconds_waited = 0;    // wall time next() waited for it (ahead)
  };
  bool done() const { return next_index_ >= static_cast<int>(frames_.size()); }
  // The next frame, refitted and rendered. Rethrows what preparing it threw (a frame of another
  // vertex count: std::invalid_argument).
  Frame next();

 private:
  struct Prepared {
    std::unique_ptr<Body> body;
    WornFrameMaps maps;
    double seconds_body = 0;
  };
  Prepared prepare(int index, std::unique_ptr<Body> spare);
  void launch();

  const std::vector<MatrixX3d>& frames_;
  WornMapRenderer renderer_;
  double seconds_;
  bool ahead_;
  int next_index_ = 1;
  std::unique_ptr<Body> current_, spare_;
  std::future<Prepared> pending_;
};

}  // namespace virtual_tryon
