#include "virtual_tryon/core/drape/frames_ahead.h"

#include <chrono>
#include <stdexcept>
#include <utility>

namespace virtual_tryon {
namespace {
using Clock = std::chrono::steady_clock;
double since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }
}  // namespace

FramesAhead::FramesAhead(std::unique_ptr<Body> first, const std::vector<MatrixX3d>& frames, WornMapRenderer renderer,
                         double seconds, bool ahead)
    : frames_(frames), renderer_(std::move(renderer)), seconds_(seconds), ahead_(ahead), current_(std::move(first)) {
  if (!current_) throw std::invalid_argument("FramesAhead: no first body");
  if (!(seconds_ > 0)) throw std::invalid_argument("FramesAhead: the frame interval must be positive");
  // Beside the caller's work, the views are rendered one after the other (the caller's thread is
  // the other core's).
  if (ahead_) renderer_.params().parallel = false;
  launch();
}

FramesAhead::~FramesAhead() {
  if (pending_.valid()) pending_.wait();
}

// Frame `index`'s body, made from `spare` (a body two frames back, no longer in use) or, the first
// time, copied from the current one; then its maps.
FramesAhead::Prepared FramesAhead::prepare(int index, std::unique_ptr<Body> spare) {
  Prepared p;
  const auto t0 = Clock::now();
  const MatrixX3d& V = frames_[static_cast<std::size_t>(index)];
  // The first copy refits the current body's trees, built now if nothing has built them yet (a
  // garment still being draped on it): a frame is refitted, never rebuilt, whenever it is made.
  if (!spare) current_->bvh();
  p.body = spare ? std::make_unique<Body>(std::move(*spare), V) : std::make_unique<Body>(*current_, V);
  p.seconds_body = since(t0);
  p.maps = renderer_.render(*p.body, seconds_);
  return p;
}

void FramesAhead::launch() {
  if (!ahead_ || done()) return;
  pending_ = std::async(std::launch::async, [this, index = next_index_, spare = std::move(spare_)]() mutable {
    return prepare(index, std::move(spare));
  });
}

FramesAhead::Frame FramesAhead::next() {
  if (done()) throw std::out_of_range("FramesAhead: no frame left");
  Frame f;
  f.index = next_index_;
  Prepared p;
  if (ahead_) {
    const auto t0 = Clock::now();
    p = pending_.get();
    f.seconds_waited = since(t0);
  } else {
    p = prepare(next_index_, std::move(spare_));
  }
  spare_ = std::move(current_);  // the caller is done with the frame before
  current_ = std::move(p.body);
  ++next_index_;
  launch();
  f.body = current_.get();
  f.maps = std::move(p.maps);
  f.seconds_body = p.seconds_body;
  return f;
}

}  // namespace virtual_tryon
