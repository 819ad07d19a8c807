#pragma once
/// Parallel loops over index ranges on oneTBB, with a process-wide thread count.
#include <cstddef>
#include <functional>
#include <memory>

namespace penumbra {

/// Limits every parallel loop of this process to `threads` workers while alive (0 = all cores).
class ThreadLimit {
 public:
  explicit ThreadLimit(int threads);
  ~ThreadLimit();
  ThreadLimit(const ThreadLimit&) = delete;
  ThreadLimit& operator=(const ThreadLimit&) = delete;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

/// Number of worker threads parallel loops use now.
int thread_count();

/// Calls body(i) for i in [0, n) in parallel; each index once, in no particular order.
/// `grain` is the smallest number of indices handed to one task.
void parallel_for(size_t n, const std::function<void(size_t)>& body, size_t grain = 1);

/// Calls body(begin, end) on disjoint sub-ranges covering [0, n) in parallel.
void parallel_for_range(size_t n, const std::function<void(size_t, size_t)>& body, size_t grain = 1);

}  // namespace penumbra
