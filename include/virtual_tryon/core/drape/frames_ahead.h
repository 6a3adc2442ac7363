// A recorded motion's body frames, made ready ahead of the worn garment: while the cloth steps
// through frame k (WornGarment::follow), a second thread refits the body to frames k + 1 .. k + depth
// (Body's frame constructor: same faces, trees refitted) and renders their maps (WornMapRenderer).
// On two cores this takes the body's refit and the maps off the cloth's path, and a queue of a few
// frames lets a frame whose maps take long (the first frames' fresh memory, a slow moment of the
// machine) be absorbed by the frames made before it. Each frame's result is the same as stepping
// the frames one after the other (the renderer is the garment's own, copied, and renders the frames
// in order on the one thread).
//
//   FramesAhead ahead(std::move(body0), frames, worn.mapRenderer(), 1.0 / 30);
//   while (!ahead.done()) {
//     FramesAhead::Frame f = ahead.next();
//     worn.follow(*f.body, std::move(f.maps));
//   }
#pragma once

#include "virtual_tryon/core/body/body.h"
#include "virtual_tryon/core/drape/worn_maps.h"

#include <condition_variable>
#include <deque>
#include <exception>
#include <memory>
#include <mutex>
#include <thread>
#include <vector>

namespace virtual_tryon {

class FramesAhead {
 public:
  // `first`: the body on frames[0] (taken over and kept unchanged while this lives; the caller may
  // go on reading it: the first frames are made from copies of it, so that the garment can be
  // draped on the first frame while they are made ready, WornGarment::dress's mapsReady). frames (kept by the
  // caller while this lives): the body's vertices per frame (each #V by 3, as many as first has),
  // `seconds` apart (> 0). ahead: the frames are prepared on a second thread, at most `depth` (>= 1)
  // of them ready and waiting at a time, while the caller works on the one before; false: next()
  // prepares each on the calling thread (the same results, one after the other).
  static constexpr int kDefaultDepth = 3;
  FramesAhead(std::unique_ptr<Body> first, const std::vector<MatrixX3d>& frames, WornMapRenderer renderer,
              double seconds, bool ahead = true, int depth = kDefaultDepth);
  ~FramesAhead();  // stops the second thread after the frame it is preparing
  FramesAhead(const FramesAhead&) = delete;
  FramesAhead& operator=(const FramesAhead&) = delete;

  struct Frame {
    int index = 0;                // into frames (1, 2, ...)
    const Body* body = nullptr;   // valid until the next call to next()
    WornFrameMaps maps;           // for WornGarment::follow(*body, maps)
    double seconds_body = 0;      // wall time of the body's refit
    double seconds_waited = 0;    // wall time next() waited for it (ahead)
    int queued = 0;               // frames after it already made ready when it was taken (ahead)
  };
  bool done() const { return next_index_ >= static_cast<int>(frames_.size()); }
  // The next frame, refitted and rendered. Rethrows what preparing it threw (a frame of another
  // vertex count: std::invalid_argument), and so does every later call.
  Frame next();

 private:
  struct Prepared {
    std::unique_ptr<Body> body;
    WornFrameMaps maps;
    double seconds_body = 0;
    std::exception_ptr error;  // what preparing it threw
  };
  Prepared prepare(int index, std::unique_ptr<Body> spare);
  void work();  // the second thread: frames 1, 2, ... in order, at most depth_ waiting
  std::unique_ptr<Body> takeSpare();

  const std::vector<MatrixX3d>& frames_;
  WornMapRenderer renderer_;
  double seconds_;
  bool ahead_;
  int depth_;
  int next_index_ = 1;
  // first_: frames[0]'s body, the copy made for a frame without a spare; current_: the body of the
  // frame last given out; spares_: bodies no frame uses any more, refitted into later frames.
  std::unique_ptr<Body> first_, current_;
  std::vector<std::unique_ptr<Body>> spares_;
  std::mutex mutex_;  // guards ready_, spares_ and stop_
  std::condition_variable changed_;
  std::deque<Prepared> ready_;
  bool stop_ = false;
  std::exception_ptr failed_;  // a frame that could not be made: next() rethrows it from then on
  std::thread worker_;
};

}  // namespace virtual_tryon
