// Internal to the core: a loop over [0, n) shared among threads started for the call (one per
// hardware thread, at most 8, each with at least `min_per_thread` items; none outlives the call,
// so a process may fork at any time). For work whose items are independent: the result must not
// depend on how the range is cut.
#pragma once

#include <algorithm>
#include <atomic>
#include <thread>
#include <vector>

namespace virtual_tryon {

// The threads a loop may use: one per hardware thread, at most 8.
inline int workerThreads() {
  constexpr unsigned kMaxThreads = 8;
  return static_cast<int>(std::max(1u, std::min(std::thread::hardware_concurrency(), kMaxThreads)));
}

// Calls body(first, last) on disjoint sub-ranges covering [0, n), the first on the calling thread.
template <class Body>
void parallelRanges(int n, int min_per_thread, Body&& body) {
  const int threads = std::max(1, std::min(workerThreads(), n / std::max(1, min_per_thread)));
  if (threads == 1) {
    if (n > 0) body(0, n);
    return;
  }
  auto range = [&](int t) {
    body(static_cast<int>(static_cast<long long>(n) * t / threads),
         static_cast<int>(static_cast<long long>(n) * (t + 1) / threads));
  };
  std::vector<std::thread> workers;
  for (int t = 1; t < threads; ++t) workers.emplace_back(range, t);
  range(0);
  for (auto& w : workers) w.join();
}

// Calls item(i) once for every i in [0, n), the items handed out one at a time to threads
// started for the call (one per hardware thread, at most 8; one thread for fewer than
// `min_items`), so that unequal items (impact zones of a few stencils and of hundreds) share
// the threads evenly. For independent items: each writes its own result.
template <class Item>
void parallelItems(int n, int min_items, Item&& item) {
  const int threads = n < std::max(2, min_items) ? 1 : std::min(workerThreads(), n);
  if (threads == 1) {
    for (int i = 0; i < n; ++i) item(i);
    return;
  }
  std::atomic<int> next{0};
  auto work = [&] {
    for (int i = next++; i < n; i = next++) item(i);
  };
  std::vector<std::thread> workers;
  for (int t = 1; t < threads; ++t) workers.emplace_back(work);
  work();
  for (auto& w : workers) w.join();
}

}  // namespace virtual_tryon
