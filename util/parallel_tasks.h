#ifndef SOFTBENCH_UTIL_PARALLEL_TASKS_H_
#define SOFTBENCH_UTIL_PARALLEL_TASKS_H_

#include <functional>

namespace softbench {

// The cores to run on (std::thread::hardware_concurrency), at least 1: the
// one count of cores that workers, decoder threads and windows share.
int CoreCount();

// Runs task(0) ... task(count - 1) on `threads` worker threads (0: one per
// core), each index exactly once, while the calling thread calls `poll` about
// ten times a second (progress bars); returns as soon as the last task has
// finished, not at the next poll. The first exception a task throws stops
// the remaining tasks from starting and is rethrown here once all workers
// have finished.
void RunParallelTasks(int count, int threads,
                      const std::function<void(int)>& task,
                      const std::function<void()>& poll);

}  // namespace softbench

#endif  // SOFTBENCH_UTIL_PARALLEL_TASKS_H_
