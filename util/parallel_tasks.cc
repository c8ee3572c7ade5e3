#include "util/parallel_tasks.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <exception>
#include <mutex>
#include <thread>
#include <vector>

namespace softbench {

void RunParallelTasks(int count, int threads,
                      const std::function<void(int)>& task,
                      const std::function<void()>& poll) {
  if (threads <= 0) {
    threads =
        std::max(1, static_cast<int>(std::thread::hardware_concurrency()));
  }
  threads = std::max(1, std::min(threads, count));
  std::atomic<int> next{0};
  std::atomic<int> finished{0};
  std::mutex mutex;
  std::exception_ptr failure;
  std::vector<std::thread> workers;
  for (int w = 0; w < threads; ++w) {
    workers.emplace_back([&] {
      try {
        for (int i; (i = next++) < count;) task(i);
      } catch (...) {
        const std::lock_guard<std::mutex> lock(mutex);
        if (!failure) failure = std::current_exception();
        next = count;
      }
      ++finished;
    });
  }
  while (finished < threads) {
    if (poll) poll();
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
  }
  for (std::thread& worker : workers) worker.join();
  if (failure) std::rethrow_exception(failure);
}

}  // namespace softbench
