#include "util/parallel_tasks.h"

#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <stdexcept>
#include <thread>
#include <vector>

namespace softbench {
namespace {

TEST(ParallelTasks, RunsEveryIndexExactlyOnce) {
  for (int threads : {0, 1, 3, 64}) {
    std::vector<std::atomic<int>> runs(100);
    RunParallelTasks(
        100, threads, [&](int i) { ++runs[i]; }, nullptr);
    for (const std::atomic<int>& count : runs) EXPECT_EQ(count, 1) << threads;
  }
}

TEST(ParallelTasks, RethrowsTheFirstFailureAndStopsStartingTasks) {
  std::atomic<int> started{0};
  EXPECT_THROW(RunParallelTasks(
                   1000, 2,
                   [&](int i) {
                     ++started;
                     if (i == 3) throw std::runtime_error("task 3");
                     std::this_thread::sleep_for(std::chrono::milliseconds(1));
                   },
                   [] {}),
               std::runtime_error);
  EXPECT_LT(started, 1000);
}

}  // namespace
}  // namespace softbench
