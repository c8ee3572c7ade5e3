#ifndef SOFTBENCH_UTIL_PROGRESS_H_
#define SOFTBENCH_UTIL_PROGRESS_H_

#include <chrono>
#include <cstdint>
#include <string>

namespace softbench {

// A progress bar on stderr: redrawn in place on a terminal (at most 10 times a
// second), one line per 10 % otherwise (logs); silent when disabled (--quiet)
// or when the whole job ends within a second.
class ProgressBar {
 public:
  ProgressBar(std::string label, int64_t total, bool enabled);
  ~ProgressBar();
  void Update(int64_t done);
  // Ends the bar's line.
  void Finish();

 private:
  void Draw(int64_t done);

  std::string label_;
  int64_t total_;
  bool enabled_;
  bool terminal_;
  bool drawn_ = false;
  int last_decile_ = -1;
  std::chrono::steady_clock::time_point start_, last_draw_;
};

}  // namespace softbench

#endif  // SOFTBENCH_UTIL_PROGRESS_H_
