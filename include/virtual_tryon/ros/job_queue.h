// One worker thread for the node's long work (meshing a scan, automatic fits), so that callbacks
// only queue work and return. Jobs carry a key; a job posted while another with the same key is
// still waiting replaces it in place (the latest body, the latest garment: nothing stale is
// computed), jobs with different keys run in the order their keys were first posted. A running
// job is never interrupted. No ROS in here.
#pragma once

#include <condition_variable>
#include <cstddef>
#include <deque>
#include <functional>
#include <map>
#include <mutex>
#include <string>
#include <thread>

namespace virtual_tryon {

class LatestJobQueue {
 public:
  using Job = std::function<void()>;
  // `onError` receives the what() of an exception a job let out (the worker keeps running).
  explicit LatestJobQueue(std::function<void(const std::string&)> onError = nullptr);
  ~LatestJobQueue();  // lets the running job finish, drops the waiting ones, joins
  LatestJobQueue(const LatestJobQueue&) = delete;
  LatestJobQueue& operator=(const LatestJobQueue&) = delete;

  // Queues `job` under `key`; returns true when it replaced a waiting job with that key.
  bool post(const std::string& key, Job job);
  // Blocks until nothing is waiting or running (tests and shutdown).
  void waitIdle();
  std::size_t waiting() const;
  bool waiting(const std::string& key) const;  // a job with this key is waiting (not running)
  std::size_t replaced() const;  // jobs dropped because a newer one with their key came

 private:
  void run();

  mutable std::mutex mutex_;
  std::condition_variable wake_, idle_;
  std::deque<std::string> order_;
  std::map<std::string, Job> jobs_;
  bool running_ = false, stop_ = false;
  std::size_t replaced_ = 0;
  std::function<void(const std::string&)> on_error_;
  std::thread thread_;  // last: starts after the members above exist
};

}  // namespace virtual_tryon
