#include "virtual_tryon/ros/job_queue.h"

#include <exception>
#include <utility>

namespace virtual_tryon {

LatestJobQueue::LatestJobQueue(std::function<void(const std::string&)> onError)
    : on_error_(std::move(onError)), thread_(&LatestJobQueue::run, this) {}

LatestJobQueue::~LatestJobQueue() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    stop_ = true;
    order_.clear();
    jobs_.clear();
  }
  wake_.notify_all();
  thread_.join();
}

bool LatestJobQueue::post(const std::string& key, Job job) {
  bool replacedOne = false;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    if (stop_) return false;
    auto it = jobs_.find(key);
    if (it != jobs_.end()) {
      it->second = std::move(job);
      ++replaced_;
      replacedOne = true;
    } else {
      jobs_.emplace(key, std::move(job));
      order_.push_back(key);
    }
  }
  wake_.notify_one();
  return replacedOne;
}

void LatestJobQueue::waitIdle() {
  std::unique_lock<std::mutex> lock(mutex_);
  idle_.wait(lock, [this] { return stop_ || (order_.empty() && !running_); });
}

std::size_t LatestJobQueue::waiting() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return order_.size();
}

bool LatestJobQueue::waiting(const std::string& key) const {
  std::lock_guard<std::mutex> lock(mutex_);
  return jobs_.count(key) > 0;
}

std::size_t LatestJobQueue::replaced() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return replaced_;
}

void LatestJobQueue::run() {
  std::unique_lock<std::mutex> lock(mutex_);
  for (;;) {
    wake_.wait(lock, [this] { return stop_ || !order_.empty(); });
    if (stop_) break;
    const std::string key = order_.front();
    order_.pop_front();
    Job job = std::move(jobs_.at(key));
    jobs_.erase(key);
    running_ = true;
    lock.unlock();
    try {
      job();
    } catch (const std::exception& e) {
      if (on_error_) on_error_(e.what());
    } catch (...) {
      if (on_error_) on_error_("unknown exception");
    }
    lock.lock();
    running_ = false;
    if (order_.empty()) idle_.notify_all();
  }
  running_ = false;
  idle_.notify_all();
}

}  // namespace virtual_tryon
