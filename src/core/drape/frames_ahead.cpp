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
                         double seconds, bool ahead, int depth)
    : frames_(frames), renderer_(std::move(renderer)), seconds_(seconds), ahead_(ahead), depth_(depth),
      first_(std::move(first)) {
  if (!first_) throw std::invalid_argument("FramesAhead: no first body");
  if (!(seconds_ > 0)) throw std::invalid_argument("FramesAhead: the frame interval must be positive");
  if (depth_ < 1) throw std::invalid_argument("FramesAhead: at least one frame ahead");
  if (!ahead_ || done()) return;
  // Beside the caller's work, the views are rendered one after the other (the caller's thread is
  // the other core's).
  renderer_.params().parallel = false;
  worker_ = std::thread([this] { work(); });
}

FramesAhead::~FramesAhead() {
  if (!worker_.joinable()) return;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    stop_ = true;
  }
  changed_.notify_all();
  worker_.join();
}

// Frame `index`'s body, made from `spare` (a body no frame uses any more) or, without one, copied
// from the first; then its maps.
FramesAhead::Prepared FramesAhead::prepare(int index, std::unique_ptr<Body> spare) {
  Prepared p;
  const auto t0 = Clock::now();
  const MatrixX3d& V = frames_[static_cast<std::size_t>(index)];
  // A copy refits the first body's trees, built now if nothing has built them yet (a garment still
  // being draped on it): a frame is refitted, never rebuilt, whenever it is made.
  if (!spare) first_->bvh();
  p.body = spare ? std::make_unique<Body>(std::move(*spare), V) : std::make_unique<Body>(*first_, V);
  p.seconds_body = since(t0);
  p.maps = renderer_.render(*p.body, seconds_);
  return p;
}

std::unique_ptr<Body> FramesAhead::takeSpare() {
  if (spares_.empty()) return nullptr;
  std::unique_ptr<Body> b = std::move(spares_.back());
  spares_.pop_back();
  return b;
}

void FramesAhead::work() {
  for (int index = 1; index < static_cast<int>(frames_.size()); ++index) {
    std::unique_ptr<Body> spare;
    {
      std::unique_lock<std::mutex> lock(mutex_);
      changed_.wait(lock, [this] { return stop_ || static_cast<int>(ready_.size()) < depth_; });
      if (stop_) return;
      spare = takeSpare();
    }
    Prepared p;
    try {
      p = prepare(index, std::move(spare));
    } catch (...) {
      p = Prepared();
      p.error = std::current_exception();
    }
    const bool failed = static_cast<bool>(p.error);
    {
      std::lock_guard<std::mutex> lock(mutex_);
      ready_.push_back(std::move(p));
    }
    changed_.notify_all();
    if (failed) return;  // nothing after a frame that could not be made
  }
}

FramesAhead::Frame FramesAhead::next() {
  if (failed_) std::rethrow_exception(failed_);  // the frames after it were not made
  if (done()) throw std::out_of_range("FramesAhead: no frame left");
  Frame f;
  f.index = next_index_;
  Prepared p;
  std::unique_ptr<Body> previous = std::move(current_);  // the caller is done with the frame before
  if (ahead_) {
    const auto t0 = Clock::now();
    {
      std::unique_lock<std::mutex> lock(mutex_);
      if (previous) spares_.push_back(std::move(previous));
      changed_.wait(lock, [this] { return !ready_.empty(); });
      p = std::move(ready_.front());
      ready_.pop_front();
      f.queued = static_cast<int>(ready_.size());
    }
    changed_.notify_all();
    f.seconds_waited = since(t0);
  } else {
    if (previous) spares_.push_back(std::move(previous));
    p = prepare(next_index_, takeSpare());
  }
  if (p.error) {
    failed_ = p.error;
    std::rethrow_exception(p.error);
  }
  current_ = std::move(p.body);
  ++next_index_;
  f.body = current_.get();
  f.maps = std::move(p.maps);
  f.seconds_body = p.seconds_body;
  return f;
}

}  // namespace virtual_tryon
